#pragma once
// SO(3) and SE(3) helpers.
//
// Perturbation convention (used everywhere in hdvio):
//   rotations are perturbed on the right,  R (+) dtheta = R * Exp(dtheta)     (body frame),
//   positions are perturbed additively,    p (+) dp     = p + dp              (world frame).
// A pose's tangent vector is ordered [dp, dtheta]. Quaternions are Hamilton, stored by Eigen
// as (x, y, z, w). Twists for the SE(3) exponential are ordered [rho (translation), phi].
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hdvio {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaterniond;

Mat3 hat(const Vec3& w);
Vec3 vee(const Mat3& W);

// SO(3)
Mat3 so3Exp(const Vec3& phi);
Quat quatExp(const Vec3& phi);
Vec3 so3Log(const Mat3& R);
Vec3 quatLog(const Quat& q);
Mat3 rightJacobian(const Vec3& phi);         // Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d)
Mat3 rightJacobianInverse(const Vec3& phi);  // Log(Exp(phi) Exp(d)) ~= phi + Jr^-1(phi) d
Mat3 leftJacobian(const Vec3& phi);          // Exp(phi + d) ~= Exp(Jl(phi) d) Exp(phi)
Mat3 leftJacobianInverse(const Vec3& phi);

// Projects any 3x3 matrix onto the closest rotation (SVD), for accumulated round-off.
Mat3 normalizeRotation(const Mat3& R);

// Rigid transform T = (R, p) mapping points x -> R x + p.
struct Pose {
  Quat q = Quat::Identity();
  Vec3 p = Vec3::Zero();

  Pose() = default;
  Pose(const Quat& q_in, const Vec3& p_in) : q(q_in.normalized()), p(p_in) {}
  Pose(const Mat3& R, const Vec3& p_in) : q(Quat(R).normalized()), p(p_in) {}

  Mat3 R() const { return q.toRotationMatrix(); }
  Mat4 matrix() const;
  Pose inverse() const;
  Pose operator*(const Pose& o) const { return Pose(q * o.q, q * o.p + p); }
  Vec3 operator*(const Vec3& x) const { return q * x + p; }
  // The hdvio tangent convention: [dp (world), dtheta (body)].
  Pose plus(const Vec6& d) const;
  Vec6 minus(const Pose& other) const;  // this (-) other, inverse of plus
};

// SE(3) exponential and logarithm on twists [rho, phi]; T = Exp(xi) in the usual group sense.
Pose se3Exp(const Vec6& xi);
Vec6 se3Log(const Pose& T);
Mat6 se3Adjoint(const Pose& T);  // acting on twists [rho, phi]

}  // namespace hdvio
