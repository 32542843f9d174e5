// Every analytic Jacobian against central differences on the manifold, at random states.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/factors/dynamics_factor.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/prior_factors.h"
#include "hdvio/factors/relative_position_factor.h"
#include "hdvio/factors/reprojection_factor.h"
#include "test_support.h"

namespace hdvio {
namespace {
using namespace symbols;
using test::randomVec3;

constexpr int kTrials = 20;

Pose randomPose(std::mt19937& rng) {
  return Pose(quatExp(randomVec3(rng, 1.5)), randomVec3(rng, 3.0));
}

// Random measurements, then states near (not at) what they predict, so residuals are moderate
// and every bias-correction term is active.
std::vector<DynamicsStep> randomSteps(std::mt19937& rng, int n) {
  std::vector<DynamicsStep> steps(n);
  for (auto& s : steps) {
    s.dt = 0.005;
    s.gyro = randomVec3(rng, 1.0);
    s.accel = Vec3(0, 0, 9.81) + randomVec3(rng, 2.0);
    s.thrust = Vec3(0, 0, 9.0) + randomVec3(rng, 0.5);
    s.residual_force = randomVec3(rng, 0.3);
  }
  return steps;
}

Values randomStates(std::mt19937& rng, const Mat3& dR) {
  Values v;
  const Pose Ti = randomPose(rng);
  v.insertPose(X(0), Ti);
  v.insertPose(X(1), Pose(Mat3(Ti.R() * dR * so3Exp(randomVec3(rng, 0.3))), Ti.p + randomVec3(rng, 1.0)));
  for (int k = 0; k < 2; ++k) {
    v.insertVector(V(k), randomVec3(rng, 2.0));
    v.insertVector(F(k), randomVec3(rng, 1.0));
    Eigen::VectorXd b(6);
    b << randomVec3(rng, 0.05), randomVec3(rng, 0.2);
    v.insertVector(B(k), b);
  }
  return v;
}

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

// The factors' own fixed-size whitening gives the same numbers as core's dense NoiseModel.
TEST(FixedWhitening, MatchesNoiseModelCovariance) {
  std::mt19937 rng(14);
  Eigen::Matrix<double, 9, 9> A;
  for (int c = 0; c < 9; ++c) A.col(c) << randomVec3(rng, 1.0), randomVec3(rng, 1.0), randomVec3(rng, 1.0);
  const Eigen::Matrix<double, 9, 9> dense = A * A.transpose() + 0.1 * Eigen::Matrix<double, 9, 9>::Identity();
  const Vec3 variances(0.5, 2.0, 0.01);
  const FixedWhitening<12, 9> fixed(dense, variances);
  const NoiseModelPtr reference = NoiseModel::covariance(fixed.covariance());
  Eigen::Matrix<double, 12, 1> r1;
  r1 << randomVec3(rng, 1.0), randomVec3(rng, 1.0), randomVec3(rng, 1.0), randomVec3(rng, 1.0);
  Eigen::Matrix<double, 12, 1> r2 = r1;
  fixed.whitenResidual(r1.data());
  reference->whitenResidual(r2.data());
  EXPECT_LT((r1 - r2).cwiseAbs().maxCoeff(), 1e-10 * r2.cwiseAbs().maxCoeff());
  Eigen::Matrix<double, 12, 3, Eigen::RowMajor> J1;
  for (int row = 0; row < 12; ++row) J1.row(row) = randomVec3(rng, 1.0).transpose();
  Eigen::Matrix<double, 12, 3, Eigen::RowMajor> J2 = J1;
  fixed.whitenJacobian<3>(J1.data());
  reference->whitenJacobian(J2.data(), 3);
  EXPECT_LT((J1 - J2).cwiseAbs().maxCoeff(), 1e-10 * J2.cwiseAbs().maxCoeff());
  using Whitening = FixedWhitening<12, 9>;
  EXPECT_THROW(Whitening(-dense, variances), std::invalid_argument);
}

TEST(FactorJacobians, BiasBetweenFactor) {
  std::mt19937 rng(12);
  BiasBetweenFactor f(B(0), B(1), 0.1, ImuNoiseParams());
  test::expectJacobiansMatchNumerical(f, randomStates(rng, Mat3::Identity()), 1e-7);
}

void expectDynamicsJacobiansMatchNumerical(unsigned seed, const DynamicsFactorParams& params) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < kTrials; ++trial) {
    Vec6 bias;
    bias << randomVec3(rng, 0.02), randomVec3(rng, 0.1);
    auto pit = std::make_shared<PreintegratedThrust>(
        PreintegratedThrust::integrate(randomSteps(rng, 40), bias, ThrustNoiseParams()));
    DynamicsFactor f(X(0), V(0), F(0), X(1), V(1), F(1), B(0), pit, params);
    test::expectJacobiansMatchNumerical(f, randomStates(rng, pit->deltaR()), 1e-6);
  }
}

class DynamicsJacobians : public ::testing::TestWithParam<DynamicsVariant> {};

TEST_P(DynamicsJacobians, MatchNumerical) {
  DynamicsFactorParams params;
  params.variant = GetParam();
  params.force_random_walk = 0.5;
  params.force_prior_sigma = 2.0;
  expectDynamicsJacobiansMatchNumerical(13 + static_cast<int>(GetParam()), params);
}

TEST(FactorJacobians, DynamicsFactorWithDrag) {
  DynamicsFactorParams params;
  params.force_random_walk = 0.5;
  params.drag.linear = Vec3(0.3, 0.25, 0.05);
  params.drag.quadratic = Vec3(0.02, 0.03, 0.01);
  expectDynamicsJacobiansMatchNumerical(17, params);
}

INSTANTIATE_TEST_SUITE_P(AllVariants, DynamicsJacobians,
                         ::testing::Values(DynamicsVariant::kHdvio, DynamicsVariant::kVimo,
                                           DynamicsVariant::kVidFusion));

class ReprojectionJacobians : public ::testing::TestWithParam<DistortionModel> {};

TEST_P(ReprojectionJacobians, MatchNumerical) {
  const DistortionModel model = GetParam();
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28, 0.07, 2e-4, -3e-4};
  if (model == DistortionModel::kEquidistant) k = {-0.01, 0.02, -0.01, 0.003};
  const CameraModel cam(458.0, 457.0, 367.0, 248.0, model, k, 752, 480);
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
  const CameraModel cam(458.0, 457.0, 367.0, 248.0, DistortionModel::kNone, {}, 752, 480);
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
