#include "hdvio/core/lie.h"

#include <Eigen/SVD>
#include <cmath>

namespace hdvio {
namespace {
constexpr double kSmallAngle = 1e-8;
}

Mat3 hat(const Vec3& w) {
  Mat3 W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}

Vec3 vee(const Mat3& W) { return Vec3(W(2, 1), W(0, 2), W(1, 0)); }

Quat quatExp(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta < kSmallAngle) {
    // Second-order accurate and unit length after normalization.
    return Quat(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
  }
  const double half = 0.5 * theta;
  const Vec3 v = std::sin(half) / theta * phi;
  return Quat(std::cos(half), v.x(), v.y(), v.z());
}

Mat3 so3Exp(const Vec3& phi) {
  const double theta2 = phi.squaredNorm();
  const Mat3 W = hat(phi);
  if (theta2 < kSmallAngle * kSmallAngle) return Mat3::Identity() + W + 0.5 * W * W;
  const double theta = std::sqrt(theta2);
  return Mat3::Identity() + std::sin(theta) / theta * W +
         (1.0 - std::cos(theta)) / theta2 * W * W;
}

Vec3 quatLog(const Quat& q_in) {
  Quat q = q_in.normalized();
  if (q.w() < 0) q.coeffs() *= -1.0;  // shortest rotation, angle in [0, pi]
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < kSmallAngle) return 2.0 * v / q.w();
  const double theta = 2.0 * std::atan2(s, q.w());
  return theta / s * v;
}

Vec3 so3Log(const Mat3& R) { return quatLog(Quat(R)); }

Mat3 rightJacobian(const Vec3& phi) {
  const double theta2 = phi.squaredNorm();
  const Mat3 W = hat(phi);
  if (theta2 < 1e-10) return Mat3::Identity() - 0.5 * W + W * W / 6.0;
  const double theta = std::sqrt(theta2);
  return Mat3::Identity() - (1.0 - std::cos(theta)) / theta2 * W +
         (theta - std::sin(theta)) / (theta2 * theta) * W * W;
}

Mat3 rightJacobianInverse(const Vec3& phi) {
  const double theta2 = phi.squaredNorm();
  const Mat3 W = hat(phi);
  if (theta2 < 1e-10) return Mat3::Identity() + 0.5 * W + W * W / 12.0;
  const double theta = std::sqrt(theta2);
  return Mat3::Identity() + 0.5 * W +
         (1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta))) * W * W;
}

Mat3 leftJacobian(const Vec3& phi) { return rightJacobian(-phi); }
Mat3 leftJacobianInverse(const Vec3& phi) { return rightJacobianInverse(-phi); }

Mat3 normalizeRotation(const Mat3& R) {
  Eigen::JacobiSVD<Mat3> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3 V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1.0;
  return U * V.transpose();
}

Mat4 Pose::matrix() const {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = R();
  T.topRightCorner<3, 1>() = p;
  return T;
}

Pose Pose::inverse() const {
  const Quat qi = q.conjugate();
  return Pose(qi, -(qi * p));
}

Pose Pose::plus(const Vec6& d) const {
  return Pose(q * quatExp(d.tail<3>()), p + d.head<3>());
}

Vec6 Pose::minus(const Pose& other) const {
  Vec6 d;
  d.head<3>() = p - other.p;
  d.tail<3>() = quatLog(other.q.conjugate() * q);
  return d;
}

Pose se3Exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  // Translation uses the left Jacobian of SO(3) (the "V" matrix).
  return Pose(quatExp(phi), leftJacobian(phi) * rho);
}

Vec6 se3Log(const Pose& T) {
  Vec6 xi;
  const Vec3 phi = quatLog(T.q);
  xi.tail<3>() = phi;
  xi.head<3>() = leftJacobianInverse(phi) * T.p;
  return xi;
}

Mat6 se3Adjoint(const Pose& T) {
  Mat6 A = Mat6::Zero();
  const Mat3 R = T.R();
  A.topLeftCorner<3, 3>() = R;
  A.topRightCorner<3, 3>() = hat(T.p) * R;
  A.bottomRightCorner<3, 3>() = R;
  return A;
}

}  // namespace hdvio
