// A solve must not depend on where the variables happen to live in memory. Ceres keeps each
// elimination group in address order, so the bridge lays the variables out in key order first;
// this test builds the same landmarks-first problem from Values whose storage was allocated in
// opposite address orders and asks for bit-identical results.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "between_pose_factor.h"
#include "point_in_body_factor.h"
#include "hdvio/core/ceres_bridge.h"

namespace hdvio {
namespace {
using symbols::L;
using symbols::X;
using testing::PointInBodyFactor;

struct Problem {
  FactorGraph graph;
  std::vector<Key> keys;
  std::vector<Eigen::VectorXd> initial;  // ambient values, in keys' order
};

Problem makeProblem() {
  Problem pb;
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  const int poses = 8, landmarks = 60;
  std::vector<Pose> truth;
  for (int k = 0; k < poses; ++k)
    truth.emplace_back(quatExp(Vec3(0.02 * k, -0.01 * k, 0.1 * k)), Vec3(0.3 * k, 0.1 * k, 0.0));
  std::vector<Vec3> points;
  for (int j = 0; j < landmarks; ++j) points.emplace_back(4.0 * n(rng), 4.0 * n(rng), 5.0 + n(rng));
  const auto pixel = NoiseModel::isotropic(3, 0.05);
  pb.graph.add(std::make_shared<testing::PosePriorFactor>(X(0), truth[0],
                                                          NoiseModel::isotropic(6, 1e-3)));
  for (int k = 0; k < poses; ++k)
    for (int j = 0; j < landmarks; ++j) {
      const Vec3 z = truth[k].R().transpose() * (points[j] - truth[k].p) +
                     0.05 * Vec3(n(rng), n(rng), n(rng));
      pb.graph.add(std::make_shared<PointInBodyFactor>(X(k), L(j), z, pixel));
    }
  for (int k = 0; k < poses; ++k) {
    Vec6 d;
    d << 0.2 * n(rng), 0.2 * n(rng), 0.2 * n(rng), 0.05 * n(rng), 0.05 * n(rng), 0.05 * n(rng);
    const Pose start = truth[k].plus(d);
    Eigen::VectorXd x(7);
    x << start.p, start.q.coeffs();
    pb.keys.push_back(X(k));
    pb.initial.push_back(x);
  }
  for (int j = 0; j < landmarks; ++j) {
    pb.keys.push_back(L(j));
    pb.initial.push_back(points[j] + 0.3 * Vec3(n(rng), n(rng), n(rng)));
  }
  return pb;
}

// Inserts the variables in the given order, with allocations in between, so that the heap
// addresses of the variables follow that order rather than the keys'.
Values valuesInOrder(const Problem& pb, const std::vector<std::size_t>& order,
                     std::vector<std::unique_ptr<char[]>>* spacers) {
  Values v;
  for (std::size_t i : order) {
    spacers->emplace_back(new char[64 + 16 * (i % 5)]);
    if (pb.keys[i].letter() == 'x')
      v.insertPose(pb.keys[i], Pose(Quat(pb.initial[i].tail<4>()), pb.initial[i].head<3>()));
    else
      v.insertVector(pb.keys[i], pb.initial[i]);
  }
  return v;
}

// The keys sorted by where their variables live: the order Ceres would see.
std::vector<Key> addressOrder(const Values& v) {
  std::vector<Key> keys = v.keys();
  std::sort(keys.begin(), keys.end(), [&](Key a, Key b) { return v.data(a) < v.data(b); });
  return keys;
}

TEST(DeterministicSolve, ResultDoesNotDependOnVariableAddresses) {
  const Problem pb = makeProblem();
  // Allocation in key order and in reverse key order.
  std::vector<std::size_t> forward(pb.keys.size()), backward;
  for (std::size_t i = 0; i < forward.size(); ++i) forward[i] = i;
  std::sort(forward.begin(), forward.end(),
            [&](std::size_t i, std::size_t j) { return pb.keys[i] < pb.keys[j]; });
  backward.assign(forward.rbegin(), forward.rend());
  std::vector<std::unique_ptr<char[]>> spacers;
  Values a = valuesInOrder(pb, forward, &spacers);
  Values b = valuesInOrder(pb, backward, &spacers);
  // The premise: the two copies really sit in different address orders.
  ASSERT_NE(addressOrder(a), addressOrder(b));

  OptimizerOptions options;
  options.linear_solver = ceres::DENSE_SCHUR;
  options.eliminate_first = {'l'};
  options.function_tolerance = 1e-12;
  options.max_iterations = 4;  // stop before convergence hides round-off in the last digits
  const OptimizeResult ra = optimize(pb.graph, &a, options);
  const OptimizeResult rb = optimize(pb.graph, &b, options);
  ASSERT_TRUE(ra.usable && rb.usable);
  EXPECT_EQ(ra.summary.iterations.size(), rb.summary.iterations.size());
  for (Key k : pb.keys) {
    const int n = a.ambientDim(k);
    EXPECT_EQ(std::memcmp(a.data(k), b.data(k), sizeof(double) * n), 0)
        << k.str() << " differs: " << Eigen::Map<const Eigen::VectorXd>(a.data(k), n).transpose()
        << " vs " << Eigen::Map<const Eigen::VectorXd>(b.data(k), n).transpose();
  }
}

// The bridge builds problems with Ceres' safety checks off; what they would catch it checks.
TEST(DeterministicSolve, AFactorListingAKeyTwiceIsAnError) {
  const Problem pb = makeProblem();
  std::vector<std::size_t> order(pb.keys.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::vector<std::unique_ptr<char[]>> spacers;
  Values v = valuesInOrder(pb, order, &spacers);
  FactorGraph graph = pb.graph;
  graph.add(std::make_shared<testing::BetweenPoseFactor>(X(1), X(1), Pose(), NoiseModel::isotropic(6, 1.0)));
  OptimizerOptions options;
  options.linear_solver = ceres::DENSE_SCHUR;
  options.eliminate_first = {'l'};
  EXPECT_THROW(optimize(graph, &v, options), std::logic_error);
}

}  // namespace
}  // namespace hdvio
