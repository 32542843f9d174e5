// End to end through Ceres: IMU + hybrid-dynamics factors over an analytic flight recover the
// states and the external force from a perturbed start.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/core/ceres_bridge.h"
#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/prior_factors.h"
#include "test_support.h"

namespace hdvio {
namespace {
using namespace symbols;
using test::AnalyticFlight;

const Vec3 kExternalForce(0.4, -0.25, 0.15);

TEST(FactorSolve, ImuAndDynamicsRecoverStatesAndExternalForce) {
  const AnalyticFlight f;
  const double rate = 500.0;
  const auto imu = test::sampleImu(f, rate, 2.0);
  std::vector<ThrustSample> thrust;
  for (const auto& s : imu) {
    const double t = toSeconds(s.t);
    thrust.push_back({s.t, f.R(t).transpose() * (f.acc(t) - gravityWorld() - kExternalForce)});
  }
  constexpr int kKeyframes = 6;
  auto time = [](int k) { return 0.1 + 0.3 * k; };

  FactorGraph graph;
  ImuNoiseParams imu_params;
  ThrustNoiseParams thrust_params;
  DynamicsFactorParams dyn;
  dyn.force_random_walk = 0.1;
  for (int k = 0; k + 1 < kKeyframes; ++k) {
    const Timestamp ti = fromSeconds(time(k)), tj = fromSeconds(time(k + 1));
    auto pim = std::make_shared<PreintegratedImu>(PreintegratedImu::integrate(imu, ti, tj, Vec6::Zero(), imu_params));
    graph.add(std::make_shared<ImuFactor>(X(k), V(k), B(k), X(k + 1), V(k + 1), B(k + 1), pim));
    auto pit = std::make_shared<PreintegratedThrust>(
        PreintegratedThrust::integrate(imu, thrust, ti, tj, Vec6::Zero(), thrust_params));
    graph.add(std::make_shared<HdvioDynamicsFactor>(X(k), V(k), F(k), X(k + 1), V(k + 1), F(k + 1), B(k), pit, dyn));
  }
  graph.add(std::make_shared<PosePrior>(X(0), Pose(f.R(time(0)), f.p(time(0))), NoiseModel::isotropic(6, 1e-3)));
  graph.add(std::make_shared<VelocityPrior>(V(0), f.v(time(0)), NoiseModel::isotropic(3, 1e-2)));
  graph.add(std::make_shared<BiasPrior>(B(0), Vec6::Zero(), NoiseModel::isotropic(6, 1e-3)));
  graph.add(std::make_shared<ForcePrior>(F(0), Vec3::Zero(), NoiseModel::isotropic(3, 10.0)));

  std::mt19937 rng(3);
  Values values;
  for (int k = 0; k < kKeyframes; ++k) {
    const double t = time(k);
    values.insertPose(X(k), Pose(Mat3(f.R(t) * so3Exp(test::randomVec3(rng, 0.05))),
                                 f.p(t) + test::randomVec3(rng, 0.2)));
    values.insertVector(V(k), f.v(t) + test::randomVec3(rng, 0.3));
    values.insertVector(B(k), Eigen::VectorXd::Zero(6));
    values.insertVector(F(k), Vec3::Zero());
  }
  OptimizerOptions options;
  options.max_iterations = 30;
  const OptimizeResult result = optimize(graph, &values, options);
  ASSERT_TRUE(result.usable) << result.summary.BriefReport();
  for (int k = 0; k < kKeyframes; ++k) {
    const double t = time(k);
    EXPECT_LT((values.pose(X(k)).p - f.p(t)).norm(), 0.02) << "keyframe " << k;
    EXPECT_LT(so3Log(f.R(t).transpose() * values.pose(X(k)).R()).norm(), 2e-3) << "keyframe " << k;
    EXPECT_LT((values.vec3(V(k)) - f.v(t)).norm(), 0.03) << "keyframe " << k;
  }
  for (int k = 0; k + 1 < kKeyframes; ++k)
    EXPECT_LT((values.vec3(F(k)) - kExternalForce).norm(), 0.05) << "keyframe " << k;
}

}  // namespace
}  // namespace hdvio
