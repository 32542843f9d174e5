// The dynamics model each method gets from makeDynamicsModel: its extra state keys, the first
// state's force prior, the factor joining two states (class and keys), where the learned force
// enters, and which force the newest state reports.
#include "hdvio/backend/dynamics_model.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/prior_factors.h"

namespace hdvio {
namespace {
using symbols::B;
using symbols::F;
using symbols::V;
using symbols::X;

// 0.1 s of hover at 200 Hz: level, at rest, thrust equal to gravity.
struct Hover {
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
  Hover() {
    for (int n = 0; n <= 20; ++n) {
      const Timestamp t = fromSeconds(0.005 * n);
      imu.push_back({t, Vec3::Zero(), Vec3(0.0, 0.0, 9.81)});
      thrust.push_back({t, Vec3(0.0, 0.0, 9.81)});
    }
  }
  InertialBuffers buffers() const { return {imu, thrust}; }
};

NavState startState() {
  NavState s;
  s.t = 0;
  s.f_ext_W = Vec3(0.3, -0.2, 0.1);
  return s;
}

StateInterval interval(const NavState& s) {
  return {4, 5, fromSeconds(0.0), fromSeconds(0.1), s, Vec3::Zero(), 0.1};
}

TEST(DynamicsModel, VioHasNoForceState) {
  const Hover hover;
  auto model = makeDynamicsModel(defaultVioBackendOptions(VioMethod::kVio));
  EXPECT_FALSE(model->needsThrust());
  EXPECT_TRUE(model->stateKeys(4).empty());
  FactorGraph graph;
  Values values;
  model->addFirstState(4, startState(), hover.buffers(), &graph, &values);
  model->addInterval(interval(startState()), hover.buffers(), &graph, &values);
  EXPECT_TRUE(graph.empty());
  EXPECT_EQ(values.size(), 0u);
}

template <class Factor>
void expectForceModel(VioMethod method, const std::vector<Key>& factor_keys, bool newest_from_previous) {
  SCOPED_TRACE(toString(method));
  const Hover hover;
  const NavState s = startState();
  auto model = makeDynamicsModel(defaultVioBackendOptions(method));
  EXPECT_TRUE(model->needsThrust());
  EXPECT_EQ(model->stateKeys(4), std::vector<Key>{F(4)});

  // The first state: F at the start's force with a prior on it.
  FactorGraph priors;
  Values first;
  model->addFirstState(4, s, hover.buffers(), &priors, &first);
  ASSERT_EQ(priors.size(), 1u);
  EXPECT_NE(dynamic_cast<const ForcePrior*>(priors[0].get()), nullptr);
  EXPECT_EQ(priors[0]->keys(), std::vector<Key>{F(4)});
  ASSERT_TRUE(first.exists(F(4)));
  EXPECT_EQ(first.vec3(F(4)), s.f_ext_W);

  // An interval: the family's factor, F(j) starting at the force at i.
  FactorGraph graph;
  Values values;
  model->addInterval(interval(s), hover.buffers(), &graph, &values);
  ASSERT_EQ(graph.size(), 1u);
  EXPECT_NE(dynamic_cast<const Factor*>(graph[0].get()), nullptr);
  EXPECT_EQ(graph[0]->keys(), factor_keys);
  EXPECT_EQ(values.size(), 1u);
  ASSERT_TRUE(values.exists(F(5)));
  EXPECT_EQ(values.vec3(F(5)), s.f_ext_W);

  // The reported force: a state's own F; the newest one's from the previous F when the
  // factor holds the force on F_i.
  Values estimate;
  estimate.insertVector(F(4), Vec3(1.0, 0.0, 0.0));
  estimate.insertVector(F(5), Vec3(0.0, 2.0, 0.0));
  NavState newest;
  model->readState(estimate, 5, &newest);
  EXPECT_EQ(newest.f_ext_W, Vec3(0.0, 2.0, 0.0));
  model->readNewest(estimate, 4, &newest);
  EXPECT_EQ(newest.f_ext_W, newest_from_previous ? Vec3(1.0, 0.0, 0.0) : Vec3(0.0, 2.0, 0.0));
}

TEST(DynamicsModel, EachForceMethodGetsItsFactor) {
  expectForceModel<VimoDynamicsFactor>(VioMethod::kVimo, {X(4), V(4), F(4), X(5), V(5), B(4)}, true);
  expectForceModel<VidDynamicsFactor>(VioMethod::kVid, {X(4), V(4), F(4), X(5), V(5), B(4)}, true);
  expectForceModel<HdvioDynamicsFactor>(VioMethod::kHdvio,
                                        {X(4), V(4), F(4), X(5), V(5), F(5), B(4)}, false);
}

TEST(DynamicsModel, OnlyHdvioAsksForTheLearnedForce) {
  const Hover hover;
  for (VioMethod method : {VioMethod::kVio, VioMethod::kVimo, VioMethod::kVid, VioMethod::kHdvio}) {
    std::vector<std::pair<Timestamp, Timestamp>> asked;
    auto model = makeDynamicsModel(defaultVioBackendOptions(method),
                                   [&](Timestamp t_i, Timestamp t_j, const Vec3&) {
                                     asked.emplace_back(t_i, t_j);
                                     return ResidualForceFn();
                                   });
    FactorGraph graph;
    Values values;
    model->addInterval(interval(startState()), hover.buffers(), &graph, &values);
    if (method == VioMethod::kHdvio) {
      ASSERT_EQ(asked.size(), 1u);
      EXPECT_EQ(asked[0], std::make_pair(fromSeconds(0.0), fromSeconds(0.1)));
    } else {
      EXPECT_TRUE(asked.empty()) << toString(method);
    }
  }
}

}  // namespace
}  // namespace hdvio
