#include "hdvio/factors/imu_preintegration.h"

#include <cmath>

#include "hdvio/core/error.h"
#include "transition.h"

namespace hdvio {

ImuNoiseParams ImuNoiseParams::fromCalibration(const ImuCalibration& calib) {
  ImuNoiseParams p;
  p.gyro_noise_density = calib.gyro_noise_density;
  p.accel_noise_density = calib.accel_noise_density;
  p.gyro_random_walk = calib.gyro_random_walk;
  p.accel_random_walk = calib.accel_random_walk;
  return p;
}

PreintegratedImu PreintegratedImu::integrate(const std::vector<ImuSample>& samples, Timestamp t_i,
                                             Timestamp t_j, const Vec6& bias,
                                             const ImuNoiseParams& params) {
  return integrate(imuSteps(samples, t_i, t_j), bias, params);
}

PreintegratedImu PreintegratedImu::integrate(std::vector<ImuStep> steps, const Vec6& bias,
                                             const ImuNoiseParams& params) {
  ImuPreintegrator builder(bias, params, /*keep_steps=*/false);
  for (const ImuStep& s : steps) builder.add(s);
  PreintegratedImu out = builder.finish();
  out.steps_ = std::make_shared<const std::vector<ImuStep>>(std::move(steps));
  return out;
}

PreintegratedImu PreintegratedImu::reintegrated(const Vec6& bias) const {
  if (!steps_) throw std::logic_error("PreintegratedImu: built without its steps, cannot reintegrate");
  ImuPreintegrator builder(bias, params_, /*keep_steps=*/false);
  for (const ImuStep& s : *steps_) builder.add(s);
  PreintegratedImu out = builder.finish();
  out.steps_ = steps_;
  return out;
}

Mat3 PreintegratedImu::correctedDeltaR(const Vec6& b) const {
  return dR_ * so3Exp(dR_dbg_ * (b.head<3>() - bias_.head<3>()));
}

Vec3 PreintegratedImu::correctedDeltaV(const Vec6& b) const {
  const Vec6 db = b - bias_;
  return dv_ + dv_dbg_ * db.head<3>() + dv_dba_ * db.tail<3>();
}

Vec3 PreintegratedImu::correctedDeltaP(const Vec6& b) const {
  const Vec6 db = b - bias_;
  return dp_ + dp_dbg_ * db.head<3>() + dp_dba_ * db.tail<3>();
}

ImuPreintegrator::ImuPreintegrator(const Vec6& bias, const ImuNoiseParams& params, bool keep_steps)
    : keep_steps_(keep_steps) {
  if (!bias.allFinite()) throw InputError("", 0, "IMU preintegration: bias is not finite");
  state_.bias_ = bias;
  state_.params_ = params;
}

void ImuPreintegrator::add(const Vec3& gyro, const Vec3& accel, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt) || !gyro.allFinite() || !accel.allFinite())
    throw InputError("", 0, "IMU preintegration: non-finite measurement or non-positive dt");
  if (keep_steps_) steps_.push_back({dt, gyro, accel});
  PreintegratedImu& s = state_;
  const Vec3 w = gyro - s.bias_.head<3>();
  const Vec3 a = accel - s.bias_.tail<3>();
  const double dt2 = dt * dt;
  const Vec3 phi = w * dt;
  const Mat3 E = so3Exp(phi);
  const Mat3 Jr = rightJacobian(phi);
  // The acceleration is rotated to the middle of the step (second-order accurate in the
  // rotation; plain Forster uses dR_k and is first order): a_m = Exp(phi / 2) a.
  const Mat3 Eh = so3Exp(0.5 * phi);
  const Vec3 a_m = Eh * a;
  const Mat3 R_mid = s.dR_ * Eh;
  const Mat3 Ra = s.dR_ * hat(a_m);                          // dR [a_m]x
  const Mat3 da_m_dbg = (0.5 * dt) * Eh * hat(a) * rightJacobian(0.5 * phi);

  // Error-state transition for [dtheta, dv, dp] (transition.h) and noise.
  s.cov_ = detail::propagate(E.transpose(), -Ra * dt, dt, s.cov_);
  const double qg = s.params_.gyro_noise_density * s.params_.gyro_noise_density * dt;
  const double qa = s.params_.accel_noise_density * s.params_.accel_noise_density * dt;
  s.cov_.block<3, 3>(0, 0).noalias() += qg * (Jr * Jr.transpose());
  s.cov_.block<3, 3>(3, 3).diagonal().array() += qa;
  s.cov_.block<3, 3>(3, 6).diagonal().array() += 0.5 * dt * qa;
  s.cov_.block<3, 3>(6, 3).diagonal().array() += 0.5 * dt * qa;
  s.cov_.block<3, 3>(6, 6).diagonal().array() += 0.25 * dt2 * qa;

  // Bias Jacobians, using dR, dv and dR_dbg before this step.
  const Mat3 dvstep_dbg = dt * (s.dR_ * da_m_dbg - Ra * s.dR_dbg_);  // d(dR a_m dt)/d bg
  s.dp_dba_ += s.dv_dba_ * dt - 0.5 * dt2 * R_mid;
  s.dp_dbg_ += s.dv_dbg_ * dt + 0.5 * dt * dvstep_dbg;
  s.dv_dba_ -= R_mid * dt;
  s.dv_dbg_ += dvstep_dbg;
  s.dR_dbg_ = E.transpose() * s.dR_dbg_ - Jr * dt;

  // Deltas.
  const Vec3 dR_a = s.dR_ * a_m;
  s.dp_ += s.dv_ * dt + 0.5 * dt2 * dR_a;
  s.dv_ += dR_a * dt;
  s.dR_ = s.dR_ * E;
  s.dt_ += dt;
}

PreintegratedImu ImuPreintegrator::finish() const {
  if (state_.dt_ <= 0.0) throw InputError("", 0, "IMU preintegration: no measurements");
  PreintegratedImu out = state_;
  out.dR_ = normalizeRotation(out.dR_);
  out.cov_ = 0.5 * (out.cov_ + out.cov_.transpose());
  if (keep_steps_) out.steps_ = std::make_shared<const std::vector<ImuStep>>(steps_);
  return out;
}

}  // namespace hdvio
