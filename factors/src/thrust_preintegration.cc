#include "hdvio/factors/thrust_preintegration.h"

#include <cmath>

#include "hdvio/core/error.h"
#include "transition.h"

namespace hdvio {

PreintegratedThrust PreintegratedThrust::integrate(const std::vector<ImuSample>& imu,
                                                   const std::vector<ThrustSample>& thrust,
                                                   Timestamp t_i, Timestamp t_j, const Vec6& bias,
                                                   const ThrustNoiseParams& params,
                                                   const ResidualForceFn& residual_force) {
  return integrate(dynamicsSteps(imu, thrust, t_i, t_j, residual_force), bias, params);
}

PreintegratedThrust PreintegratedThrust::integrate(std::vector<DynamicsStep> steps,
                                                   const Vec6& bias,
                                                   const ThrustNoiseParams& params) {
  ThrustPreintegrator builder(bias, params, /*keep_steps=*/false);
  for (const DynamicsStep& s : steps) builder.add(s);
  PreintegratedThrust out = builder.finish();
  out.steps_ = std::make_shared<const std::vector<DynamicsStep>>(std::move(steps));
  return out;
}

PreintegratedThrust PreintegratedThrust::reintegrated(const Vec6& bias) const {
  if (!steps_)
    throw std::logic_error("PreintegratedThrust: built without its steps, cannot reintegrate");
  ThrustPreintegrator builder(bias, params_, /*keep_steps=*/false);
  for (const DynamicsStep& s : *steps_) builder.add(s);
  PreintegratedThrust out = builder.finish();
  out.steps_ = steps_;
  return out;
}

Eigen::Matrix<double, 6, 6> PreintegratedThrust::alphaBetaCovariance() const {
  Eigen::Matrix<double, 6, 6> c;
  c.topLeftCorner<3, 3>() = cov_.block<3, 3>(6, 6);
  c.topRightCorner<3, 3>() = cov_.block<3, 3>(6, 3);
  c.bottomLeftCorner<3, 3>() = cov_.block<3, 3>(3, 6);
  c.bottomRightCorner<3, 3>() = cov_.block<3, 3>(3, 3);
  return c;
}

ThrustPreintegrator::ThrustPreintegrator(const Vec6& bias, const ThrustNoiseParams& params,
                                         bool keep_steps)
    : keep_steps_(keep_steps) {
  if (!bias.allFinite()) throw InputError("", 0, "thrust preintegration: bias is not finite");
  state_.bias_ = bias;
  state_.params_ = params;
}

void ThrustPreintegrator::add(const DynamicsStep& step) {
  const double dt = step.dt;
  if (!(dt > 0.0) || !std::isfinite(dt) || !step.gyro.allFinite() || !step.accel.allFinite() ||
      !step.thrust.allFinite() || !step.residual_force.allFinite())
    throw InputError("", 0, "thrust preintegration: non-finite measurement or non-positive dt");
  if (keep_steps_) steps_.push_back(step);
  PreintegratedThrust& s = state_;
  const ThrustNoiseParams& np = s.params_;
  const Vec3 w = step.gyro - s.bias_.head<3>();
  const Vec3 f = step.thrust + step.residual_force;
  const Vec3 u = step.accel - s.bias_.tail<3>() - f;  // accelerometer minus model
  const double dt2 = dt * dt;
  const Vec3 phi = w * dt;
  const Mat3 E = so3Exp(phi);
  const Mat3 Jr = rightJacobian(phi);
  // Forces are rotated to the middle of the step (as in imu_preintegration.cc).
  const Mat3 Eh = so3Exp(0.5 * phi);
  const Mat3 Jrh_dt = (0.5 * dt) * rightJacobian(0.5 * phi);
  const Vec3 f_m = Eh * f, u_m = Eh * u;
  const Mat3 R_mid = s.dR_ * Eh;
  const Mat3 Rf = s.dR_ * hat(f_m);

  // Error-state transition for x = [dtheta, beta, alpha] and the gyro bias drift d inside the
  // interval: x' = A x + Bd d, d' = d + n_b, with Bd = [-Jr dt; 0; 0]. Kept as blocks
  // (P = cov_, C = cov(x, d), drift variance sigma^2 t I) rather than one 12x12 matrix.
  const Mat3 Et = E.transpose(), X = -Rf * dt;
  const Mat3 Bd = -Jr * dt;  // rows 0-2 of Bd; the others are zero
  const Eigen::Matrix<double, 9, 3> AC = detail::applyTransition<3>(Et, X, dt, cross_);
  s.cov_ = detail::propagate(Et, X, dt, s.cov_);
  const Eigen::Matrix<double, 9, 3> AC_BdT = AC * Bd.transpose();
  s.cov_.leftCols<3>() += AC_BdT;
  s.cov_.topRows<3>() += AC_BdT.transpose();
  s.cov_.block<3, 3>(0, 0).noalias() += drift_variance_ * (Bd * Bd.transpose());
  cross_ = AC;
  cross_.topRows<3>() += drift_variance_ * Bd;
  drift_variance_ += np.gyro_random_walk * np.gyro_random_walk * dt;

  // Noise: gyro on dtheta; thrust + residual-force (per axis) and thrust direction on beta/alpha.
  // Discrete covariances are density^2 / dt.
  const double gd = np.gyro_noise_density;
  s.cov_.block<3, 3>(0, 0).noalias() += (gd * gd * dt) * (Jr * Jr.transpose());
  const Vec3 force_var = np.thrust_noise_density.cwiseAbs2() + np.residual_force_noise_density.cwiseAbs2();
  const Mat3 M = R_mid * hat(step.thrust);  // thrust direction noise: f_T -> Exp(n) f_T
  const double dd = np.thrust_direction_noise_density;
  const Mat3 G = R_mid * force_var.asDiagonal() * R_mid.transpose() + dd * dd * (M * M.transpose());
  s.cov_.block<3, 3>(3, 3).noalias() += dt * G;
  s.cov_.block<3, 3>(3, 6).noalias() += (0.5 * dt2) * G;
  s.cov_.block<3, 3>(6, 3).noalias() += (0.5 * dt2) * G;
  s.cov_.block<3, 3>(6, 6).noalias() += (0.25 * dt2 * dt) * G;

  // Bias Jacobians before the deltas (they use dR, dR_dbg of the previous step).
  const Mat3 dbeta_step_dbg = dt * (R_mid * hat(f) * Jrh_dt - Rf * s.dR_dbg_);
  s.dalpha_dbg_ += s.dbeta_dbg_ * dt + 0.5 * dt * dbeta_step_dbg;
  s.dbeta_dbg_ += dbeta_step_dbg;
  s.dgamma_dbg_ += dt * (R_mid * hat(u) * Jrh_dt - s.dR_ * hat(u_m) * s.dR_dbg_);
  s.dgamma_dba_ -= dt * R_mid;
  s.dR_dbg_ = E.transpose() * s.dR_dbg_ - Jr * dt;

  s.drag_nodes_.push_back({R_mid, s.dt_ + 0.5 * dt, dt, 0.0, step.thrust.norm(), w});
  const Vec3 dR_f = s.dR_ * f_m;
  s.alpha_ += s.beta_ * dt + 0.5 * dt2 * dR_f;
  s.beta_ += dR_f * dt;
  s.gamma_ += s.dR_ * u_m * dt;
  s.dR_ = s.dR_ * E;
  s.dt_ += dt;
}

PreintegratedThrust ThrustPreintegrator::finish() const {
  if (state_.dt_ <= 0.0) throw InputError("", 0, "thrust preintegration: no measurements");
  PreintegratedThrust out = state_;
  out.dR_ = normalizeRotation(out.dR_);
  out.cov_ = 0.5 * (out.cov_ + out.cov_.transpose());
  for (PreintegratedThrust::DragNode& n : out.drag_nodes_) {
    n.w_alpha = n.w_beta * (out.dt_ - n.s);
    n.s /= out.dt_;
  }
  if (keep_steps_) out.steps_ = std::make_shared<const std::vector<DynamicsStep>>(steps_);
  return out;
}

}  // namespace hdvio
