#include "hdvio/core/noise_model.h"

#include <Eigen/LU>
#include <gtest/gtest.h>

namespace hdvio {
namespace {

TEST(NoiseModel, CovarianceWhitensToIdentity) {
  Eigen::Matrix3d C;
  C << 4.0, 1.0, 0.5, 1.0, 2.0, 0.2, 0.5, 0.2, 1.0;
  const auto noise = NoiseModel::covariance(C);
  const Eigen::MatrixXd S = noise->sqrtInformationMatrix();
  // S C S^T = I  <=>  S^T S = C^-1.
  EXPECT_LT((S * C * S.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  const auto info = NoiseModel::information(C.inverse());
  const Eigen::MatrixXd S2 = info->sqrtInformationMatrix();
  EXPECT_LT((S2.transpose() * S2 - C.inverse()).norm(), 1e-10);
}

TEST(NoiseModel, DiagonalWhitensResidualAndJacobian) {
  const auto noise = NoiseModel::diagonal(Eigen::Vector2d(0.5, 2.0));
  double r[2] = {1.0, 1.0};
  noise->whitenResidual(r);
  EXPECT_DOUBLE_EQ(r[0], 2.0);
  EXPECT_DOUBLE_EQ(r[1], 0.5);
  double J[4] = {1.0, 2.0, 3.0, 4.0};  // row-major 2x2
  noise->whitenJacobian(J, 2);
  EXPECT_DOUBLE_EQ(J[1], 4.0);
  EXPECT_DOUBLE_EQ(J[2], 1.5);
}

TEST(NoiseModel, RejectsInvalidSigmas) {
  EXPECT_THROW(NoiseModel::diagonal(Eigen::Vector2d(1.0, 0.0)), std::invalid_argument);
  Eigen::Matrix2d bad;
  bad << 1.0, 2.0, 2.0, 1.0;  // indefinite
  EXPECT_THROW(NoiseModel::covariance(bad), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio
