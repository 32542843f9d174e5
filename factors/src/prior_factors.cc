#include "hdvio/factors/prior_factors.h"

namespace hdvio {

PosePrior::PosePrior(Key pose, const Pose& prior, NoiseModelPtr noise)
    : FactorT({pose}, std::move(noise)), prior_(prior) {}

bool PosePrior::evaluateError(const double* const* x, double* residual, double** jac) const {
  Eigen::Map<const Vec3> p(x[0]);
  Eigen::Map<const Quat> q(x[0] + 3);
  Eigen::Map<Vec6> r(residual);
  r.head<3>() = p - prior_.p;
  r.tail<3>() = quatLog(prior_.q.conjugate() * q);
  if (jac && jac[0]) {
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J(jac[0]);
    J.setZero();
    J.topLeftCorner<3, 3>().setIdentity();
    J.bottomRightCorner<3, 3>() = rightJacobianInverse(r.tail<3>());
  }
  return true;
}

}  // namespace hdvio
