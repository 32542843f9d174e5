#include <gtest/gtest.h>

#include <random>

#include "between_pose_factor.h"
#include "hdvio/core/numerical_jacobian.h"

namespace hdvio {
namespace {
using symbols::X;

Pose randomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Pose(quatExp(Vec3(n(rng), n(rng), n(rng))), Vec3(n(rng), n(rng), n(rng)));
}

TEST(FactorT, AnalyticTangentJacobiansMatchNumeric) {
  std::mt19937 rng(11);
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Identity() * 0.01;
  cov(0, 1) = cov(1, 0) = 0.004;
  const auto noise = NoiseModel::covariance(cov);
  for (int trial = 0; trial < 20; ++trial) {
    Values values;
    values.insertPose(X(0), randomPose(rng));
    values.insertPose(X(1), randomPose(rng));
    testing::BetweenPoseFactor between(X(0), X(1), randomPose(rng), noise);
    EXPECT_LT(maxJacobianError(between, values), 1e-7) << "trial " << trial;
    testing::PosePriorFactor prior(X(0), randomPose(rng), noise);
    EXPECT_LT(maxJacobianError(prior, values), 1e-7) << "trial " << trial;
  }
}

TEST(FactorT, WhitenedErrorUsesNoiseModel) {
  Values values;
  values.insertPose(X(0), Pose(Quat::Identity(), Vec3(1.0, 0.0, 0.0)));
  testing::PosePriorFactor prior(X(0), Pose(), NoiseModel::isotropic(6, 0.5));
  Eigen::VectorXd r;
  ASSERT_TRUE(prior.whitenedError(values, &r));
  EXPECT_NEAR(r[0], 2.0, 1e-12);
  EXPECT_NEAR(prior.error(values), 2.0, 1e-12);  // 0.5 * 2^2
}

}  // namespace
}  // namespace hdvio
