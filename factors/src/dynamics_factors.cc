#include "hdvio/factors/dynamics_factors.h"

#include <cmath>

namespace hdvio {
namespace {
using Mat9x6 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;
using Mat9x3 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;

// x and jac in the order (X_i, V_i, F_i, X_j, V_j, B_i), the VIMO / VID keys.
Mat3 evaluateSixKeys(const PointMassDynamics& dynamics, const double* const* x, double* residual,
                     double** jac) {
  PointMassDynamics::Jacobians J;
  if (jac) J = {jac[0], jac[1], jac[2], jac[3], jac[4], jac[5]};
  return dynamics.evaluate({x[0], x[1], x[2], x[3], x[4], x[5]}, residual, jac ? &J : nullptr);
}
}  // namespace

NoiseModelPtr HdvioDynamicsFactor::noiseFor(const PreintegratedThrust& pit,
                                            const DynamicsFactorParams& params) {
  return PointMassDynamics::noiseFor(pit, params.drag, params.force_random_walk * std::sqrt(pit.dt()));
}

HdvioDynamicsFactor::HdvioDynamicsFactor(Key pose_i, Key vel_i, Key force_i, Key pose_j, Key vel_j,
                                         Key force_j, Key bias_i,
                                         std::shared_ptr<const PreintegratedThrust> pit,
                                         const DynamicsFactorParams& params)
    : FactorT({pose_i, vel_i, force_i, pose_j, vel_j, force_j, bias_i}, noiseFor(*pit, params)),
      PointMassDynamics(std::move(pit), params.drag) {}

bool HdvioDynamicsFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  PointMassDynamics::Jacobians J;
  if (jac) J = {jac[0], jac[1], jac[2], jac[3], jac[4], jac[6]};
  evaluate({x[0], x[1], x[2], x[3], x[4], x[6]}, residual, jac ? &J : nullptr);
  Eigen::Map<const Vec3> f_i(x[2]), f_j(x[5]);
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residual);
  r.segment<3>(6) = f_j - f_i;
  if (!jac) return true;
  if (jac[2]) Eigen::Map<Mat9x3>(jac[2]).block<3, 3>(6, 0) = -1.0 * Mat3::Identity();
  if (jac[5]) {
    Eigen::Map<Mat9x3> Jf(jac[5]);
    Jf.setZero();
    Jf.block<3, 3>(6, 0) = Mat3::Identity();
  }
  return true;
}

bool VimoDynamicsFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  evaluateSixKeys(*this, x, residual, jac);
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residual);
  r.segment<3>(6) = Eigen::Map<const Vec3>(x[2]);
  if (jac && jac[2]) Eigen::Map<Mat9x3>(jac[2]).block<3, 3>(6, 0) = 1.0 * Mat3::Identity();
  return true;
}

bool VidDynamicsFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  const Mat3 Ri = evaluateSixKeys(*this, x, residual, jac);
  const PreintegratedThrust& pit = preintegrated();
  const double dt = pit.dt();
  Eigen::Map<const Vec3> f_i(x[2]);
  Eigen::Map<const Vec6> b_i(x[5]);
  const Vec3 mean_body = pit.correctedGamma(Vec6(b_i)) / dt;  // R_i^T f_ext from accel - thrust
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residual);
  r.segment<3>(6) = f_i - Ri * mean_body;
  if (!jac) return true;
  if (jac[0]) Eigen::Map<Mat9x6>(jac[0]).block<3, 3>(6, 3) = Ri * hat(mean_body);
  if (jac[2]) Eigen::Map<Mat9x3>(jac[2]).block<3, 3>(6, 0) = 1.0 * Mat3::Identity();
  if (jac[5]) {
    Eigen::Map<Mat9x6> J(jac[5]);
    J.block<3, 3>(6, 0) = -Ri * pit.dgamma_dbg() / dt;
    J.block<3, 3>(6, 3) = -Ri * pit.dgamma_dba() / dt;
  }
  return true;
}

}  // namespace hdvio
