#include "hdvio/core/noise_model.h"

#include <cmath>

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

// A diagonal model's fixed-size whitening (what FactorT uses for diagonal noise) gives the
// dynamic path's bits, row by row.
TEST(NoiseModel, DiagonalFixedWhiteningGivesTheDynamicPathsBits) {
  const auto noise = NoiseModel::diagonal(Eigen::Vector3d(0.7, 3.1, 1.3e-3));
  Eigen::Matrix<double, 3, 6, Eigen::RowMajor> J_dynamic;
  for (int k = 0; k < 18; ++k) J_dynamic.data()[k] = std::sin(1.0 + k) * std::pow(10.0, k % 5 - 2);
  const Eigen::Matrix<double, 3, 6, Eigen::RowMajor> J = J_dynamic;
  Eigen::Matrix<double, 3, 6, Eigen::RowMajor> J_fixed = J;
  Eigen::Vector3d r_dynamic(0.3, -7.1, 2.2e-4), r_fixed = r_dynamic;
  noise->whitenJacobian(J_dynamic.data(), 6);
  noise->whitenJacobianDiagonal<3, 6>(J_fixed.data());
  noise->whitenResidual(r_dynamic.data());
  noise->whitenResidualDiagonal<3>(r_fixed.data());
  for (int k = 0; k < 18; ++k) EXPECT_EQ(J_fixed.data()[k], J_dynamic.data()[k]) << k;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(r_fixed(k), r_dynamic(k)) << k;
  EXPECT_DOUBLE_EQ(J_fixed(2, 4), J(2, 4) / 1.3e-3);  // row 2 by its own sigma
}

// The block-diagonal model's fixed-size whitening, its dynamic path and core's dense model built
// from the same covariance agree, and it reports the covariance it was given.
TEST(NoiseModel, BlockDiagonalMatchesDenseModel) {
  Eigen::Matrix<double, 4, 4> A;
  A << 1.0, 0.2, -0.3, 0.1, 0.0, 2.0, 0.5, -0.4, 0.3, 0.1, 1.5, 0.2, -0.2, 0.6, 0.0, 0.8;
  const Eigen::Matrix<double, 4, 4> dense = A * A.transpose() + 0.1 * Eigen::Matrix4d::Identity();
  const Eigen::Vector2d variances(0.5, 0.01);
  const auto block = NoiseModel::blockDiagonal<6, 4>(dense, variances);
  EXPECT_EQ(block->denseBlock(), 4);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(6, 6);
  C.topLeftCorner(4, 4) = dense;
  C.bottomRightCorner(2, 2) = variances.asDiagonal();
  // The independent entries are kept as inverse sigmas: their variances come back to round-off.
  EXPECT_LT((block->covarianceMatrix() - C).cwiseAbs().maxCoeff(), 1e-15);
  const auto reference = NoiseModel::covariance(C);
  EXPECT_LT((reference->covarianceMatrix() - C).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::Matrix<double, 6, 1> r0;
  r0 << 0.3, -1.2, 0.7, 2.0, -0.4, 0.9;
  Eigen::Matrix<double, 6, 1> r1 = r0, r2 = r0, r3 = r0;
  block->whitenResidualFixed<6, 4>(r1.data());
  block->whitenResidual(r2.data());
  reference->whitenResidual(r3.data());
  EXPECT_LT((r1 - r3).cwiseAbs().maxCoeff(), 1e-10 * r3.cwiseAbs().maxCoeff());
  EXPECT_LT((r2 - r3).cwiseAbs().maxCoeff(), 1e-10 * r3.cwiseAbs().maxCoeff());
  Eigen::Matrix<double, 6, 3, Eigen::RowMajor> J0;
  for (int i = 0; i < 18; ++i) J0.data()[i] = 0.1 * i - 0.7;
  Eigen::Matrix<double, 6, 3, Eigen::RowMajor> J1 = J0, J2 = J0, J3 = J0;
  block->whitenJacobianFixed<6, 4, 3>(J1.data());
  block->whitenJacobian(J2.data(), 3);
  reference->whitenJacobian(J3.data(), 3);
  EXPECT_LT((J1 - J3).cwiseAbs().maxCoeff(), 1e-10 * J3.cwiseAbs().maxCoeff());
  EXPECT_LT((J2 - J3).cwiseAbs().maxCoeff(), 1e-10 * J3.cwiseAbs().maxCoeff());
  const Eigen::Matrix<double, 4, 4> indefinite = -dense;
  EXPECT_THROW((NoiseModel::blockDiagonal<6, 4>(indefinite, variances)), std::invalid_argument);
}

TEST(NoiseModel, RejectsInvalidSigmas) {
  EXPECT_THROW(NoiseModel::diagonal(Eigen::Vector2d(1.0, 0.0)), std::invalid_argument);
  Eigen::Matrix2d bad;
  bad << 1.0, 2.0, 2.0, 1.0;  // indefinite
  EXPECT_THROW(NoiseModel::covariance(bad), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio
