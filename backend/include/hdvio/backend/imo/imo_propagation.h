#pragma once
// One IMU propagation step of the IMO filter, by the blocks of its error-state transition.
// With the error state [dtheta, dv, dp, dbg, dba] the discrete transition is
//   A = [ Tt   0    0   Tg   0  ]      right error: Tt = dR^T, Tg = -Jr(phi) dt
//                                      left error:  Tt = I,    Tg = -R_next Jr(phi) dt
//       [ Vt   I    0   Vg   Va ]      V* = d(velocity)/d(*)
//       [ Pt  dt I  I   Pg   Pa ]      P* = dt/2 V*   (p gets v dt + acc dt^2 / 2)
//       [ 0    0    0   I    0  ]
//       [ 0    0    0   0    I  ]
// and the IMU noise enters like the biases (B = A's bias columns). Multiplying by the five
// non-trivial 3x3 blocks instead of the dense 15x15 matrix makes a step about 5x cheaper; the
// result equals the dense A P A' + B Q B' up to rounding (test_imo checks 1e-12). docs/imo.md.
#include <Eigen/Core>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio::imo {

using Mat15 = Eigen::Matrix<double, 15, 15>;

// How the attitude error dtheta perturbs a rotation: on the right, R = R_hat Exp(dtheta) (body
// frame, the hdvio convention), or on the left, R = Exp(dtheta) R_hat (world frame, as the IMO
// and TLIO releases' scekf.py). v, p and the biases are additive in both.
enum class RotationError { kRight, kLeft };

struct ImoNominalState {
  Timestamp t = 0;
  Mat3 R = Mat3::Identity();
  Vec3 v = Vec3::Zero();
  Vec3 p = Vec3::Zero();
  Vec3 bg = Vec3::Zero();
  Vec3 ba = Vec3::Zero();
};

struct StepTransition {
  Mat3 theta_theta = Mat3::Identity();  // dR^T (right), I (left)
  Mat3 theta_bg = Mat3::Zero();         // -Jr(phi) dt (right), -R_next Jr(phi) dt (left)
  Mat3 vel_theta = Mat3::Zero();        // -R_mid [a]x dR_half^T dt (right), -[R_mid a]x dt (left)
  Mat3 vel_bg = Mat3::Zero();
  Mat3 vel_ba = Mat3::Zero();           // -R_mid dt
  double dt = 0.0;

  Mat15 dense() const;                                // A
  Eigen::Matrix<double, 15, 6> noiseInput() const;    // B, columns [gyro noise, accel noise]
};

struct NominalStep {
  ImoNominalState state;  // time not advanced
  StepTransition transition;
};

// Nominal state after dt with bias-free rates held constant over the step (specific force
// rotated with the mid-step attitude, or with the start attitude when start_attitude: the
// IMO release's first-order step) and its transition for the given attitude error convention.
NominalStep propagateStep(const ImoNominalState& x, const Vec3& gyro, const Vec3& accel, double dt,
                          const Vec3& gravity, bool start_attitude = false,
                          RotationError rotation_error = RotationError::kRight);

// X <- A X for any 15-row block (the lazily accumulated transition product).
void applyTransition(const StepTransition& A, Mat15* X);

// P <- A P A' + B diag(gyro_var, accel_var) B' for a symmetric P, with per-axis variances of the
// held noise samples (sigma^2 / dt). Random walks and symmetrization are the caller's.
void propagateCovariance(const StepTransition& A, double gyro_var, double accel_var, Mat15* P);

}  // namespace hdvio::imo
