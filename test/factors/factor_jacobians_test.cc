// Every analytic Jacobian against central differences on the manifold, at random states.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/inverse_depth_reprojection_factor.h"
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

// An anchored inverse-depth landmark seen from a second pose and from its anchor: Jacobians, and
// the same residuals as the world-point factor on the same point (one measurement, two
// parameterizations).
class InverseDepthJacobians : public ::testing::TestWithParam<DistortionModel> {};

TEST_P(InverseDepthJacobians, MatchNumericalAndTheWorldPointFactor) {
  const DistortionModel model = GetParam();
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28, 0.07, 2e-4, -3e-4};
  if (model == DistortionModel::kEquidistant) k = {-0.01, 0.02, -0.01, 0.003};
  const CameraModel cam(752, 480, 458.0, 457.0, 367.0, 248.0, model, k);
  std::mt19937 rng(41 + static_cast<int>(model));
  for (int trial = 0; trial < kTrials; ++trial) {
    const Pose T_WBa = randomPose(rng);
    const Pose T_BC(quatExp(randomVec3(rng, 0.5)), randomVec3(rng, 0.1));
    // The second pose 0.5 m and 0.2 rad from the anchor, so the point stays in front of both.
    const Pose T_WBk = T_WBa * Pose(quatExp(randomVec3(rng, 0.2)), randomVec3(rng, 0.5));
    std::uniform_real_distribution<double> u(-0.5, 0.5), depth(2.0, 8.0);
    const double z = depth(rng);
    const Vec3 l_Ca(u(rng) * z, u(rng) * z, z);
    const Vec3 lambda = inverseDepthFromAnchorPoint(l_Ca);
    Values v;
    v.insertPose(X(0), T_WBa);
    v.insertPose(X(1), T_WBk);
    v.insertVector(L(0), lambda);
    const Vec2 z_uv = Vec2(370.0, 250.0) + randomVec3(rng, 5.0).head<2>();
    InverseDepthReprojectionFactor f(X(0), X(1), L(0), z_uv, cam, T_BC,
                                     pixelNoise(1.5, RobustLoss::kHuber, 2.0));
    InverseDepthAnchorFactor a(L(0), z_uv, cam, pixelNoise(1.5));
    test::expectJacobiansMatchNumerical(f, v, 1e-6);
    test::expectJacobiansMatchNumerical(a, v, 1e-6);

    Values w;
    w.insertPose(X(0), T_WBa);
    w.insertPose(X(1), T_WBk);
    w.insertVector(L(1), inverseDepthWorldPoint(T_WBa, T_BC, lambda));
    EXPECT_LT((w.vec3(L(1)) - T_WBa * (T_BC * l_Ca)).norm(), 1e-12);
    const ReprojectionFactor g(X(1), L(1), z_uv, cam, T_BC, pixelNoise(1.5));
    const ReprojectionFactor g_anchor(X(0), L(1), z_uv, cam, T_BC, pixelNoise(1.5));
    Eigen::VectorXd r_f, r_g;
    ASSERT_TRUE(f.whitenedError(v, &r_f));
    ASSERT_TRUE(g.whitenedError(w, &r_g));
    EXPECT_LT((r_f - r_g).norm(), 1e-9);
    ASSERT_TRUE(a.whitenedError(v, &r_f));
    ASSERT_TRUE(g_anchor.whitenedError(w, &r_g));
    EXPECT_LT((r_f - r_g).norm(), 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, InverseDepthJacobians,
                         ::testing::Values(DistortionModel::kNone, DistortionModel::kRadialTangential,
                                           DistortionModel::kEquidistant));

// A point 10 km away (rho -> 0 is the limit) still constrains the relative rotation and hardly
// the translation; a non-positive rho and a point behind the second camera are invalid.
TEST(InverseDepthReprojectionFactor, FarPointsConstrainRotationAndBadDepthsAreInvalid) {
  const CameraModel cam(752, 480, 458.0, 457.0, 367.0, 248.0);
  const Pose T_BC;
  const Pose T_WBk(quatExp(Vec3(0.0, 0.02, 0.0)), Vec3(0.3, 0.0, 0.0));
  Values v;
  v.insertPose(X(0), Pose());
  v.insertPose(X(1), T_WBk);
  v.insertVector(L(0), Vec3(0.1, -0.05, 1e-4));
  InverseDepthReprojectionFactor f(X(0), X(1), L(0), Vec2(400, 230), cam, T_BC, pixelNoise(1.0));
  Eigen::VectorXd r0, r;
  ASSERT_TRUE(f.whitenedError(v, &r0));
  EXPECT_TRUE(r0.allFinite());
  test::expectJacobiansMatchNumerical(f, v, 1e-6);
  v.updatePose(X(1), T_WBk * Pose(quatExp(Vec3(0.0, 0.01, 0.0)), Vec3::Zero()));
  ASSERT_TRUE(f.whitenedError(v, &r));
  EXPECT_GT((r - r0).norm(), 3.0);  // 0.01 rad is ~4.6 px
  v.updatePose(X(1), Pose(T_WBk.q, T_WBk.p + Vec3(0.0, 0.1, 0.0)));
  ASSERT_TRUE(f.whitenedError(v, &r));
  EXPECT_LT((r - r0).norm(), 0.01);  // 10 cm at 10 km is ~0.005 px
  v.update(L(0), Vec3(0.1, -0.05, 0.0));
  EXPECT_FALSE(f.whitenedError(v, &r));
  v.update(L(0), Vec3(0.1, -0.05, 0.5));  // 2 m ahead of the anchor,
  v.updatePose(X(1), Pose(quatExp(Vec3(0.0, M_PI, 0.0)), Vec3::Zero()));  // camera k looks away
  EXPECT_FALSE(f.whitenedError(v, &r));
}

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
