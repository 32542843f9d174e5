#include "hdvio/factors/relative_position_factor.h"

namespace hdvio {
namespace {
using Mat36R = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
}

RelativePositionFactor::RelativePositionFactor(Key pose_i, Key pose_j, const Vec3& d,
                                               NoiseModelPtr noise)
    : FactorT({pose_i, pose_j}, std::move(noise)), d_(d) {}

bool RelativePositionFactor::evaluateError(const double* const* x, double* residual,
                                           double** jac) const {
  Eigen::Map<const Vec3> p_i(x[0]), p_j(x[1]);
  Eigen::Map<Vec3> r(residual);
  r = p_j - p_i - d_;
  if (jac && jac[0]) {
    Eigen::Map<Mat36R> J(jac[0]);
    J.setZero();
    J.leftCols<3>() = -Mat3::Identity();
  }
  if (jac && jac[1]) {
    Eigen::Map<Mat36R> J(jac[1]);
    J.setZero();
    J.leftCols<3>() = Mat3::Identity();
  }
  return true;
}

}  // namespace hdvio
