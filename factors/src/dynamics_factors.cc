#include "hdvio/factors/dynamics_factors.h"

#include <cmath>
#include <stdexcept>

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
  const double rw = params.force_random_walk;
  const double dt = pit.dt();
  if (!(rw > 0.0) || !std::isfinite(rw))
    throw std::invalid_argument("dynamics factor: force random walk must be positive and finite");
  // The walk between the interpolated end points is a Brownian bridge B(t), independent of
  // f_j - f_i; its integrals into alpha (weight dt - t) and beta (weight 1) have per axis
  // Var = q dt^5/45, q dt^3/12 and Cov = q dt^4/24 (q = rw^2, isotropic, so the same in frame i).
  // The drag law's own error (drag_sigma) adds its held-over-the-interval covariance.
  const double q = rw * rw;
  Eigen::Matrix<double, 6, 6> cov =
      pit.alphaBetaCovariance() + dragCovariance(pit, params.drag, params.sigma_velocity_i, params.sigma_velocity_j);
  cov.topLeftCorner<3, 3>().diagonal().array() += q * std::pow(dt, 5) / 45.0;
  cov.topRightCorner<3, 3>().diagonal().array() += q * std::pow(dt, 4) / 24.0;
  cov.bottomLeftCorner<3, 3>().diagonal().array() += q * std::pow(dt, 4) / 24.0;
  cov.bottomRightCorner<3, 3>().diagonal().array() += q * std::pow(dt, 3) / 12.0;
  return NoiseModel::blockDiagonal<9, 6>(cov, Vec3::Constant(q * dt));
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
  const Mat3 Ri = evaluate({x[0], x[1], x[2], x[3], x[4], x[6]}, residual, jac ? &J : nullptr);
  Eigen::Map<const Vec3> f_i(x[2]), f_j(x[5]);
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residual);
  // evaluate() held f_i over [i, j]; the walk's force is interpolated linearly to f_j instead
  // (its rest is the bridge noise of noiseFor): alpha gets (f_i/3 + f_j/6) dt^2 in place of
  // f_i dt^2/2, beta (f_i + f_j) dt/2 in place of f_i dt.
  const double dt = preintegrated().dt();
  const double ca = dt * dt / 6.0, cb = 0.5 * dt;
  const Mat3 RiT = Ri.transpose();
  const Vec3 df_i = RiT * (f_i - f_j);
  r.segment<3>(0) += ca * df_i;
  r.segment<3>(3) += cb * df_i;
  r.segment<3>(6) = f_j - f_i;
  if (!jac) return true;
  if (jac[0]) {
    Eigen::Map<Mat9x6> Jp(jac[0]);
    Jp.block<3, 3>(0, 3) += ca * hat(df_i);
    Jp.block<3, 3>(3, 3) += cb * hat(df_i);
  }
  if (jac[2]) {
    Eigen::Map<Mat9x3> Jf(jac[2]);
    Jf.block<3, 3>(0, 0) += ca * RiT;
    Jf.block<3, 3>(3, 0) += cb * RiT;
    Jf.block<3, 3>(6, 0) = -1.0 * Mat3::Identity();
  }
  if (jac[5]) {
    Eigen::Map<Mat9x3> Jf(jac[5]);
    Jf.block<3, 3>(0, 0) = -ca * RiT;
    Jf.block<3, 3>(3, 0) = -cb * RiT;
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
