#include "hdvio/backend/imo/imo_propagation.h"

namespace hdvio::imo {
namespace {

constexpr int kTheta = 0, kVel = 3, kPos = 6, kBg = 9, kBa = 12;
using Rows3 = Eigen::Matrix<double, 3, 15>;

// Re-orthonormalize through a unit quaternion (cheaper than an SVD at IMU rate).
Mat3 orthonormalized(const Mat3& R) { return Quat(R).normalized().toRotationMatrix(); }

}  // namespace

Mat15 StepTransition::dense() const {
  Mat15 A = Mat15::Identity();
  A.block<3, 3>(kTheta, kTheta) = theta_theta;
  A.block<3, 3>(kTheta, kBg) = theta_bg;
  A.block<3, 3>(kVel, kTheta) = vel_theta;
  A.block<3, 3>(kVel, kBg) = vel_bg;
  A.block<3, 3>(kVel, kBa) = vel_ba;
  A.block<3, 3>(kPos, kTheta) = 0.5 * dt * vel_theta;
  A.block<3, 3>(kPos, kVel) = dt * Mat3::Identity();
  A.block<3, 3>(kPos, kBg) = 0.5 * dt * vel_bg;
  A.block<3, 3>(kPos, kBa) = 0.5 * dt * vel_ba;
  return A;
}

Eigen::Matrix<double, 15, 6> StepTransition::noiseInput() const {
  // Measurement noise enters exactly like a bias error (measured = true + bias + noise).
  const Mat15 A = dense();
  Eigen::Matrix<double, 15, 6> B;
  B.leftCols<3>() = A.middleCols<3>(kBg);
  B.rightCols<3>() = A.middleCols<3>(kBa);
  B.block<3, 3>(kBg, 0).setZero();
  B.block<3, 3>(kBa, 3).setZero();
  return B;
}

NominalStep propagateStep(const ImoNominalState& x, const Vec3& gyro, const Vec3& accel, double dt,
                          const Vec3& gravity, bool start_attitude, RotationError rotation_error) {
  const Vec3 w = gyro - x.bg;
  const Vec3 a = accel - x.ba;
  const Vec3 phi = w * dt;
  // The specific force is rotated with the mid-step attitude R Exp(phi / 2): second-order
  // accurate, where the release's R_k is first order (the tests measure both rates).
  const Mat3 M = so3Exp(0.5 * phi);
  const Mat3 dR = M * M;  // Exp(phi), one trigonometric evaluation fewer
  const Mat3 Ma = start_attitude ? Mat3::Identity() : M;  // attitude the force is rotated with
  const Mat3 Rm = x.R * Ma;
  const Vec3 acc_w = Rm * a;

  NominalStep s;
  s.state = x;
  s.state.R = orthonormalized(x.R * dR);
  s.state.v = x.v + (acc_w + gravity) * dt;
  s.state.p = x.p + x.v * dt + 0.5 * (acc_w + gravity) * dt * dt;

  // Error dynamics, v, p and biases additive. The bias rows are the same in both conventions
  // except the attitude's: a gyro-bias error rotates the step by Exp(-Jr(phi) dbg dt) on the
  // right of dR, i.e. in the body frame at the step's end.
  StepTransition& A = s.transition;
  A.dt = dt;
  A.vel_bg = start_attitude ? Mat3::Zero()                              // d(acc_w)/d(dbg) dt
                            : Mat3(Rm * hat(a) * rightJacobian(0.5 * phi) * (0.5 * dt * dt));
  A.vel_ba = -Rm * dt;
  if (rotation_error == RotationError::kLeft) {
    // R = Exp(dtheta) R_hat: a world-frame error is carried unchanged by R <- R dR, and
    // Exp(dtheta) R_m a = acc_w + dtheta x acc_w.
    A.theta_theta = Mat3::Identity();
    A.theta_bg = -s.state.R * rightJacobian(phi) * dt;
    A.vel_theta = -hat(acc_w) * dt;
  } else {
    // R = R_hat Exp(dtheta): the body-frame error is rotated into the next body frame.
    A.theta_theta = dR.transpose();
    A.theta_bg = -rightJacobian(phi) * dt;
    A.vel_theta = -Rm * hat(a) * Ma.transpose() * dt;                  // d(acc_w)/d(dtheta) dt
  }
  return s;
}

void applyTransition(const StepTransition& A, Mat15* X_ptr) {
  Mat15& X = *X_ptr;
  const Rows3 v_old = X.middleRows<3>(kVel);
  Rows3 v_new = v_old;
  v_new.noalias() += A.vel_theta * X.middleRows<3>(kTheta);
  v_new.noalias() += A.vel_bg * X.middleRows<3>(kBg);
  v_new.noalias() += A.vel_ba * X.middleRows<3>(kBa);
  Rows3 theta_new;
  theta_new.noalias() = A.theta_theta * X.middleRows<3>(kTheta);
  theta_new.noalias() += A.theta_bg * X.middleRows<3>(kBg);
  // Position rows: p + dt v + dt/2 (V* x) = p + dt/2 (v_old + v_new).
  X.middleRows<3>(kPos) += (0.5 * A.dt) * (v_old + v_new);
  X.middleRows<3>(kVel) = v_new;
  X.middleRows<3>(kTheta) = theta_new;
}

void propagateCovariance(const StepTransition& A, double gyro_var, double accel_var, Mat15* P) {
  Mat15 M = *P;
  applyTransition(A, &M);  // A P
  *P = M.transpose();      // P A' (P symmetric)
  applyTransition(A, P);   // A P A'
  // B diag(q) B': gyro noise through the bias-gyro column (rows theta, v, p), accel noise through
  // the bias-accel column (rows v, p).
  Eigen::Matrix<double, 9, 3> G;
  G << A.theta_bg, A.vel_bg, 0.5 * A.dt * A.vel_bg;
  Eigen::Matrix<double, 6, 3> F;
  F << A.vel_ba, 0.5 * A.dt * A.vel_ba;
  // Lazy products: Eigen would call its GEMM for the 9 x 3 x 9 one (sizes above its threshold).
  P->topLeftCorner<9, 9>().noalias() += gyro_var * G.lazyProduct(G.transpose());
  P->block<6, 6>(kVel, kVel).noalias() += accel_var * F.lazyProduct(F.transpose());
}

}  // namespace hdvio::imo
