#pragma once
// Hybrid-dynamics preintegration (HDVIO, Cioffi et al. RSS 2023, Eqs. 4-6).
//
// The dynamics model is v_dot = R (f_T + f_res) + f_ext + g: mass-normalized collective thrust
// f_T and learned residual force f_res in the body frame, external force f_ext in the world
// frame. Between keyframes i and j, with the gyro-integrated rotation dR_ik (gyro bias bg held
// fixed, like IMU preintegration) and f_k = Exp(w_k dt / 2) (f_T,k + f_res,k) (rotated to the
// middle of the step, as in imu_preintegration.h):
//   beta_ij  = sum dR_ik f_k dt                      (velocity-like)
//   alpha_ij = sum [beta_ik dt + 1/2 dR_ik f_k dt^2] (position-like)
// Also accumulated, for the VID-Fusion force mean: gamma_ij = sum dR_ik (a_k - ba - f_k) dt
// (same mid-step rotation),
// the accelerometer-minus-model specific force in frame i (gamma / dt_ij ~= R_i^T f_ext).
//
// The covariance is over [dtheta, beta, alpha] and is propagated together with the gyro bias
// drift inside the interval from: gyro noise, thrust noise (per axis, body frame), residual
// force noise (per axis), thrust-direction noise (the thrust vector rotated by a small random
// angle) and the gyro bias random walk. All noises are continuous-time densities; the model is
// linearized, so the per-sample direction noise (density / sqrt(dt)) should stay below ~0.1 rad.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"
#include "hdvio/factors/imu_preintegration.h"
#include "hdvio/factors/measurement_steps.h"

namespace hdvio {

struct ThrustNoiseParams {
  Vec3 thrust_noise_density = Vec3::Constant(0.1);       // m/s^2/sqrt(Hz), body axes
  double thrust_direction_noise_density = 0.01;          // rad/sqrt(Hz)
  Vec3 residual_force_noise_density = Vec3::Zero();      // m/s^2/sqrt(Hz), body axes
  double gyro_noise_density = 1.7e-4;                    // rad/s/sqrt(Hz)
  double gyro_random_walk = 1.9e-5;                      // rad/s^2/sqrt(Hz)
  Vec3 gravity = gravityWorld();
};

class PreintegratedThrust {
 public:
  // Integrates IMU (gyro, and accel for gamma) and thrust samples over [t_i, t_j]; bias = [bg, ba].
  static PreintegratedThrust integrate(const std::vector<ImuSample>& imu,
                                       const std::vector<ThrustSample>& thrust, Timestamp t_i,
                                       Timestamp t_j, const Vec6& bias,
                                       const ThrustNoiseParams& params,
                                       const ResidualForceFn& residual_force = nullptr);
  static PreintegratedThrust integrate(std::vector<DynamicsStep> steps, const Vec6& bias,
                                       const ThrustNoiseParams& params);
  PreintegratedThrust reintegrated(const Vec6& bias) const;

  double dt() const { return dt_; }
  const Mat3& deltaR() const { return dR_; }
  const Vec3& alpha() const { return alpha_; }
  const Vec3& beta() const { return beta_; }
  const Vec3& gamma() const { return gamma_; }
  const Mat9& covariance() const { return cov_; }  // [dtheta, beta, alpha]
  Eigen::Matrix<double, 6, 6> alphaBetaCovariance() const;  // [alpha, beta]
  const Vec6& bias() const { return bias_; }
  const ThrustNoiseParams& params() const { return params_; }
  const Mat3& dR_dbg() const { return dR_dbg_; }
  const Mat3& dalpha_dbg() const { return dalpha_dbg_; }
  const Mat3& dbeta_dbg() const { return dbeta_dbg_; }
  const Mat3& dgamma_dbg() const { return dgamma_dbg_; }
  const Mat3& dgamma_dba() const { return dgamma_dba_; }

  // One per integration step, for drag evaluated at the state's velocity (drag_model.h): the
  // rotation to frame i at the middle of the step, the step's middle as a fraction of dt(), and
  // the weights with which a force held over the step enters beta (dt_k) and alpha
  // (dt_k * (dt() - t_mid,k)), and the step's collective thrust |T| (m/s^2; the law's rotor term).
  struct DragNode {
    Mat3 dR = Mat3::Identity();
    double s = 0.0, w_beta = 0.0, w_alpha = 0.0;
    double thrust = 0.0;
    Vec3 omega = Vec3::Zero();  // body rate (gyro minus bias), for the law's sigma
  };
  const std::vector<DragNode>& dragNodes() const { return drag_nodes_; }

  Vec3 correctedAlpha(const Vec3& bg) const { return alpha_ + dalpha_dbg_ * (bg - bias_.head<3>()); }
  Vec3 correctedBeta(const Vec3& bg) const { return beta_ + dbeta_dbg_ * (bg - bias_.head<3>()); }
  Vec3 correctedGamma(const Vec6& b) const {
    const Vec6 db = b - bias_;
    return gamma_ + dgamma_dbg_ * db.head<3>() + dgamma_dba_ * db.tail<3>();
  }

 private:
  friend class ThrustPreintegrator;
  PreintegratedThrust() = default;

  double dt_ = 0.0;
  Mat3 dR_ = Mat3::Identity();
  Vec3 alpha_ = Vec3::Zero(), beta_ = Vec3::Zero(), gamma_ = Vec3::Zero();
  Mat9 cov_ = Mat9::Zero();
  Mat3 dR_dbg_ = Mat3::Zero(), dalpha_dbg_ = Mat3::Zero(), dbeta_dbg_ = Mat3::Zero();
  Mat3 dgamma_dbg_ = Mat3::Zero(), dgamma_dba_ = Mat3::Zero();
  Vec6 bias_ = Vec6::Zero();
  std::vector<DragNode> drag_nodes_;  // s holds t_mid until finish()
  ThrustNoiseParams params_;
  std::shared_ptr<const std::vector<DynamicsStep>> steps_;
};

class ThrustPreintegrator {
 public:
  ThrustPreintegrator(const Vec6& bias, const ThrustNoiseParams& params, bool keep_steps = true);
  void add(const DynamicsStep& step);
  PreintegratedThrust finish() const;

 private:
  PreintegratedThrust state_;
  // Gyro bias drift inside the interval: its covariance with [dtheta, beta, alpha] and its own
  // (isotropic) variance; propagated with state_.cov_ (a 12-state filter kept as blocks).
  Eigen::Matrix<double, 9, 3> cross_ = Eigen::Matrix<double, 9, 3>::Zero();
  double drift_variance_ = 0.0;
  bool keep_steps_;
  std::vector<DynamicsStep> steps_;
};

}  // namespace hdvio
