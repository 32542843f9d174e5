#pragma once
// The IMO / TLIO stochastic-cloning error-state EKF (Cioffi et al., RA-L 2023, Sec. III-C;
// Liu et al., TLIO, RA-L 2020). Nominal state R, v, p, bg, ba (world z up, body = IMU frame)
// plus a list of past clones (R, v, p). The error state is ordered
//   [dtheta, dv, dp, dbg, dba | clone_0 (dtheta, dv, dp) | clone_1 ...]
// with rotations perturbed on the right (R = R_hat Exp(dtheta), the hdvio convention; the
// default) or on the left (R = Exp(dtheta) R_hat, world frame, as the IMO release's scekf.py:
// options.rotation_error) and everything else additive. A measurement's attitude_jacobian is
// always for the right perturbation (the left filter converts it: dtheta_right = R^T
// dtheta_left). IMU noise is given as continuous-time densities and discretized per step. Updates use a relative-position measurement between two clones,
//   z = p_j - p_i - C v_i - J dtheta_i   (C = J = 0 for network displacements; the drag
//                                         model's displacement depends on v_i and theta_i)
// with the covariance update in Joseph form. IMU steps: imo_propagation.h. docs/imo.md.
#include <vector>

#include "hdvio/backend/imo/imo_propagation.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio::imo {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

constexpr int kStateDim = 15;  // evolving error state
constexpr int kCloneDim = 9;   // dtheta, dv, dp of one clone

struct ImoFilterOptions {
  // Continuous-time IMU noise densities. Defaults: the IMO release's per-sample sigmas
  // (accel 0.1 m/s^2, gyro 1e-3 rad/s) at its 100 Hz rate, i.e. sigma * sqrt(0.01 s).
  double gyro_noise_density = 1e-4;   // rad/s/sqrt(Hz)
  double accel_noise_density = 1e-2;  // m/s^2/sqrt(Hz)
  double gyro_random_walk = 1e-4;     // rad/s^2/sqrt(Hz)  (paper sigma_nbg)
  double accel_random_walk = 1e-2;    // m/s^3/sqrt(Hz)    (paper sigma_nba)
  // Initial standard deviations (IMO release defaults).
  double init_attitude_sigma = 10.0 * M_PI / 180.0;  // roll, pitch (rad)
  double init_yaw_sigma = 10.0 * M_PI / 180.0;       // rad
  double init_velocity_sigma = 1.0;                  // m/s
  double init_position_sigma = 1.0;                  // m
  double init_gyro_bias_sigma = 1e-4;                // rad/s
  double init_accel_bias_sigma = 1e-4;               // m/s^2
  // Chi-square gating of updates: reject when r' S^-1 r > factor * 11.345 (3 dof, 99 %).
  // factor <= 0 disables the test (the IMO release default).
  double mahalanobis_factor = -1.0;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  // Propagate as the IMO release's scekf.propagate: each IMU interval takes its newer sample
  // (zero-order hold, in ImoStepper) and the specific force is rotated with the attitude at
  // the step's start (first order). false: the two samples' mean, mid-step attitude.
  bool release_propagation = false;
  // The attitude error convention (imo_propagation.h). The initial attitude sigmas are taken in
  // that error's frame: body axes (right) or world axes (left; the release's "yaw" sigma is
  // then about world z).
  RotationError rotation_error = RotationError::kRight;
};

struct ImoClone {
  Timestamp t = 0;
  Mat3 R = Mat3::Identity();
  Vec3 v = Vec3::Zero();
  Vec3 p = Vec3::Zero();
};

// Displacement measurement between clones i < j:
//   z = p_j - p_i - C v_i - J dtheta_i,   C = velocity_coefficient I + velocity_matrix,
// J = attitude_jacobian (a model prediction's sensitivity to clone i's attitude error,
// linearized at the estimate).
struct RelativePositionMeasurement {
  int clone_i = 0;
  int clone_j = 0;
  Vec3 z = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
  double velocity_coefficient = 0.0;      // s
  Mat3 velocity_matrix = Mat3::Zero();    // s
  Mat3 attitude_jacobian = Mat3::Zero();  // m/rad
};

enum class UpdateOutcome { kApplied, kRejectedByGate };

// The innovation of a displacement update: residual r = z - h(x) before the update, its
// covariance S = H P H' + R and the normalized innovation squared r' S^-1 r (3 on average,
// 1 per axis, when P and R describe the errors).
struct Innovation {
  Vec3 residual = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
  double nis = 0.0;
};

// One discrete propagation step of the nominal state with bias-free rates held constant over dt,
// and its error-state transition A (15 x 15) and noise input B (15 x 6, [gyro; accel] noise).
// Dense form of propagateStep (imo_propagation.h) for tests and analysis; the filter uses the blocks.
struct PropagationStep {
  ImoNominalState state;
  Mat15 A;
  Eigen::Matrix<double, kStateDim, 6> B;
};
PropagationStep propagateNominal(const ImoNominalState& x, const Vec3& gyro, const Vec3& accel,
                                 double dt, const Vec3& gravity,
                                 bool start_attitude = false,
                                 RotationError rotation_error = RotationError::kRight);

class ImoFilter {
 public:
  explicit ImoFilter(const ImoFilterOptions& options);

  // Initial state with the option's initial covariance and no clones.
  void initialize(const ImoNominalState& x0);

  // Propagate by dt with the (raw) gyro and accel held constant over the step.
  void propagate(const Vec3& gyro, const Vec3& accel, Timestamp t_next);

  // Clone (R, v, p) of the current state, appended after the existing clones.
  void addClone();
  // Drops clone k from the state (its information is kept in the remaining covariance).
  void marginalizeClone(int k);

  UpdateOutcome update(const RelativePositionMeasurement& m);
  // Generic EKF update (imo_filter_generic_update.cc): residual r = z - h(x) (m), its Jacobian
  // H (m x (15 + 9 N)) with respect to the error state, covariance R (m x m); Joseph form.
  // gate_probability in (0, 1) rejects the update when r' S^-1 r exceeds the chi-square
  // quantile with m degrees of freedom; <= 0 applies every update.
  // H is in the filter's convention: build it for the right perturbation and pass it through
  // jacobianInFilterConvention.
  UpdateOutcome updateGeneric(const VecX& r, const MatX& H, const MatX& R, double gate_probability = 0.0);
  // A Jacobian (any rows, 15 + 9 N columns) whose attitude columns are for the right
  // perturbation, in the filter's convention (unchanged for the right one).
  MatX jacobianInFilterConvention(const MatX& H_right) const;

  const ImoNominalState& state() const { return x_; }
  const std::vector<ImoClone>& clones() const { return clones_; }
  int findClone(Timestamp t) const;  // index, or -1
  // Full covariance (15 + 9 N square).
  MatX covariance() const;
  double lastMahalanobis() const { return last_chi2_; }
  // Of the last update() (displacement measurements; gated ones too).
  const Innovation& lastInnovation() const { return last_innovation_; }

  // h(x) and its Jacobian for a measurement (public for tests).
  Vec3 predictMeasurement(const RelativePositionMeasurement& m) const;
  MatX measurementJacobian(const RelativePositionMeasurement& m) const;
  // Apply an error-state correction (15 + 9 N) to the nominal state and clones.
  void inject(const VecX& dx);

 private:
  // A right-perturbation attitude Jacobian block (3 columns) for the rotation R, in the
  // filter's own convention.
  Mat3 attitudeBlock(const Mat3& J_right, const Mat3& R) const;
  Mat3 perturbed(const Mat3& R, const Vec3& dtheta) const;
  void syncCrossCovariance();
  int dim() const { return kStateDim + kCloneDim * static_cast<int>(clones_.size()); }
  // The covariance proper: the top-left dim() x dim() block of the storage P_.
  auto cov() { return P_.topLeftCorner(dim(), dim()); }
  auto cov() const { return P_.topLeftCorner(dim(), dim()); }
  // Grows the storage (geometrically, keeping the covariance) to hold at least n x n.
  void reserve(int n);

  ImoFilterOptions options_;
  ImoNominalState x_;
  std::vector<ImoClone> clones_;
  // Covariance storage, evolving state first; only cov() is meaningful. Cloning and
  // marginalization work in place, so a run allocates it once. The evolving-clone cross block
  // is propagated lazily: the true block is phi_ * cov()(0:15, 15:) (phi_ = product of
  // transitions since the last sync).
  MatX P_;
  Mat15 phi_ = Mat15::Identity();
  double last_chi2_ = 0.0;
  Innovation last_innovation_;
};

}  // namespace hdvio::imo
