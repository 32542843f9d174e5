// Every analytic Jacobian against central differences on the manifold, at random states.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/prior_factors.h"
#include "hdvio/factors/relative_position_factor.h"
#include "hdvio/factors/reprojection_factor.h"
#include "test_support.h"

namespace hdvio {
namespace {
using namespace symbols;
using test::randomPose;
using test::randomStates;
using test::randomSteps;
using test::randomVec3;

constexpr int kTrials = 20;

TEST(FactorJacobians, ImuFactor) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<ImuStep> steps;
    for (const auto& s : randomSteps(rng, 40)) steps.push_back({s.dt, s.gyro, s.accel});
    Vec6 bias;
    bias << randomVec3(rng, 0.02), randomVec3(rng, 0.1);
    auto pim = std::make_shared<PreintegratedImu>(PreintegratedImu::integrate(steps, bias, ImuNoiseParams()));
    ImuFactor f(X(0), V(0), B(0), X(1), V(1), B(1), pim);
    test::expectJacobiansMatchNumerical(f, randomStates(rng, pim->deltaR()), 1e-6);
  }
}

TEST(FactorJacobians, BiasBetweenFactor) {
  std::mt19937 rng(12);
  BiasBetweenFactor f(B(0), B(1), 0.1, ImuNoiseParams());
  test::expectJacobiansMatchNumerical(f, randomStates(rng, Mat3::Identity()), 1e-7);
}

template <class Factor>
void expectDynamicsJacobiansMatchNumerical(unsigned seed, const DynamicsFactorParams& params) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    Vec6 bias;
    bias << randomVec3(rng, 0.02), randomVec3(rng, 0.1);
    auto pit = std::make_shared<PreintegratedThrust>(
        PreintegratedThrust::integrate(randomSteps(rng, 40), bias, ThrustNoiseParams()));
    const auto f = test::makeDynamics<Factor>(pit, params);
    test::expectJacobiansMatchNumerical(*f, randomStates(rng, pit->deltaR()), 1e-6);
  }
}

template <class Factor>
class DynamicsJacobians : public ::testing::Test {};
using DynamicsFactorTypes = ::testing::Types<HdvioDynamicsFactor, VimoDynamicsFactor, VidDynamicsFactor>;
TYPED_TEST_SUITE(DynamicsJacobians, DynamicsFactorTypes);

TYPED_TEST(DynamicsJacobians, MatchNumerical) {
  DynamicsFactorParams params;
  params.force_random_walk = 0.5;
  params.force_prior_sigma = 2.0;
  expectDynamicsJacobiansMatchNumerical<TypeParam>(13, params);
}

TYPED_TEST(DynamicsJacobians, MatchNumericalWithDrag) {
  DynamicsFactorParams params;
  params.force_random_walk = 0.5;
  params.force_prior_sigma = 2.0;
  params.drag.linear = Vec3(0.3, 0.25, 0.05);
  params.drag.quadratic = Vec3(0.02, 0.03, 0.01);
  params.drag.rotor = Vec3(0.2, 0.15, 0.07);
  params.drag.lift = 0.016;
  expectDynamicsJacobiansMatchNumerical<TypeParam>(17, params);
}

class ReprojectionJacobians : public ::testing::TestWithParam<DistortionModel> {};

TEST_P(ReprojectionJacobians, MatchNumerical) {
  const DistortionModel model = GetParam();
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28, 0.07, 2e-4, -3e-4};
  if (model == DistortionModel::kEquidistant) k = {-0.01, 0.02, -0.01, 0.003};
  const CameraModel cam(752, 480, 458.0, 457.0, 367.0, 248.0, model, k);
  std::mt19937 rng(21 + static_cast<int>(model));
  for (int trial = 0; trial < kTrials; ++trial) {
    const Pose T_WB = randomPose(rng);
    const Pose T_BC(quatExp(randomVec3(rng, 0.5)), randomVec3(rng, 0.1));
    // A landmark 1-8 m in front of the camera, within +-35 degrees of the axis.
    std::uniform_real_distribution<double> u(-0.7, 0.7), depth(1.0, 8.0);
    const double z = depth(rng);
    const Vec3 l_C(u(rng) * z, u(rng) * z, z);
    Values v;
    v.insertPose(X(0), T_WB);
    v.insertVector(L(0), T_WB * (T_BC * l_C));
    ReprojectionFactor f(X(0), L(0), Vec2(370.0, 250.0) + randomVec3(rng, 5.0).head<2>(), cam, T_BC,
                         pixelNoise(1.5, RobustLoss::kHuber, 2.0));
    test::expectJacobiansMatchNumerical(f, v, 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, ReprojectionJacobians,
                         ::testing::Values(DistortionModel::kNone, DistortionModel::kRadialTangential,
                                           DistortionModel::kEquidistant));

TEST(ReprojectionFactor, PointBehindCameraIsInvalid) {
  const CameraModel cam(752, 480, 458.0, 457.0, 367.0, 248.0);
  Values v;
  v.insertPose(X(0), Pose());
  v.insertVector(L(0), Vec3(0.1, 0.2, -3.0));
  ReprojectionFactor f(X(0), L(0), Vec2(300, 200), cam, Pose(), pixelNoise(1.0));
  Eigen::VectorXd r;
  EXPECT_FALSE(f.whitenedError(v, &r));
}

TEST(FactorJacobians, RelativePositionAndPriors) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Values v = randomStates(rng, so3Exp(randomVec3(rng, 1.0)));
    Mat3 A;
    A << randomVec3(rng, 1.0), randomVec3(rng, 1.0), randomVec3(rng, 1.0);
    RelativePositionFactor rel(X(0), X(1), randomVec3(rng, 1.0),
                               NoiseModel::covariance(A * A.transpose() + 0.1 * Mat3::Identity()));
    test::expectJacobiansMatchNumerical(rel, v, 1e-7);
    PosePrior pose(X(0), randomPose(rng), NoiseModel::isotropic(6, 0.1));
    test::expectJacobiansMatchNumerical(pose, v, 1e-6);
    VelocityPrior vel(V(0), randomVec3(rng, 1.0), NoiseModel::isotropic(3, 0.3));
    test::expectJacobiansMatchNumerical(vel, v, 1e-7);
    BiasPrior bias(B(0), (Eigen::Matrix<double, 6, 1>() << randomVec3(rng, 0.1), randomVec3(rng, 0.1)).finished(), NoiseModel::isotropic(6, 0.01));
    test::expectJacobiansMatchNumerical(bias, v, 1e-7);
    ForcePrior force(F(1), randomVec3(rng, 1.0), NoiseModel::isotropic(3, 2.0));
    test::expectJacobiansMatchNumerical(force, v, 1e-7);
  }
}

}  // namespace
}  // namespace hdvio
