#include "hdvio/factors/inverse_depth_reprojection_factor.h"

#include <stdexcept>

namespace hdvio {

Vec3 inverseDepthWorldPoint(const Pose& T_WBa, const Pose& T_BC, const Vec3& lambda) {
  return T_WBa * (T_BC * Vec3(Vec3(lambda.x(), lambda.y(), 1.0) / lambda.z()));
}

Vec3 inverseDepthFromAnchorPoint(const Vec3& p_Ca) {
  return Vec3(p_Ca.x() / p_Ca.z(), p_Ca.y() / p_Ca.z(), 1.0 / p_Ca.z());
}

InverseDepthReprojectionFactor::InverseDepthReprojectionFactor(
    Key anchor_pose, Key pose, Key inverse_depth, const Vec2& measured_uv,
    const CameraModel& camera, const Pose& T_BC, NoiseModelPtr noise)
    : FactorT({anchor_pose, pose, inverse_depth}, std::move(noise)),
      measured_(measured_uv),
      camera_(camera) {
  if (this->dim() != 2)
    throw std::invalid_argument("InverseDepthReprojectionFactor: noise must be 2-D");
  if (anchor_pose == pose)
    throw std::invalid_argument(
        "InverseDepthReprojectionFactor: the anchor's own observation is InverseDepthAnchorFactor");
  R_BC_ = T_BC.R();
  t_BC_ = T_BC.p;
  const Pose T_CB = T_BC.inverse();
  R_CB_ = T_CB.R();
  t_CB_ = T_CB.p;
}

bool InverseDepthReprojectionFactor::evaluateError(const double* const* x, double* residual,
                                                   double** jac) const {
  Eigen::Map<const Vec3> p_a(x[0]), p_k(x[1]);
  Eigen::Map<const Quat> q_a(x[0] + 3), q_k(x[1] + 3);
  const double rho = x[2][2];
  if (!(rho > 0.0)) return false;
  const Vec3 m_C(x[2][0], x[2][1], 1.0);
  const Mat3 R_a = q_a.toRotationMatrix();
  const Mat3 R_kT = q_k.toRotationMatrix().transpose();
  const Vec3 b = R_BC_ * m_C + rho * t_BC_;               // rho * landmark in body a
  const Vec3 m = R_kT * (R_a * b + rho * (p_a - p_k));  // rho * landmark in body k
  const Vec3 h = R_CB_ * m + rho * t_CB_;               // rho * landmark in camera k
  if (!(h.z() > CameraModel::kMinDepth * rho)) return false;
  Vec2 uv;
  Mat23 J_uv;
  if (!camera_.project(h, &uv, jac ? &J_uv : nullptr)) return false;
  Eigen::Map<Vec2> r(residual);
  r = uv - measured_;
  if (!jac) return true;
  // Pose tangents as ReprojectionFactor's: world-frame position, body-frame rotation.
  const Mat23 J_m = J_uv * R_CB_;  // d uv / d m
  if (jac[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J(jac[0]);
    J.leftCols<3>() = rho * J_m * R_kT;
    J.rightCols<3>() = -J_m * R_kT * R_a * hat(b);
  }
  if (jac[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J(jac[1]);
    J.leftCols<3>() = -rho * J_m * R_kT;
    J.rightCols<3>() = J_m * hat(m);
  }
  if (jac[2]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jac[2]);
    J.leftCols<2>() = J_m * R_kT * R_a * R_BC_.leftCols<2>();
    J.col(2) = J_m * (R_kT * (R_a * t_BC_ + p_a - p_k)) + J_uv * t_CB_;
  }
  return true;
}

InverseDepthAnchorFactor::InverseDepthAnchorFactor(Key inverse_depth, const Vec2& measured_uv,
                                                   const CameraModel& camera, NoiseModelPtr noise)
    : FactorT({inverse_depth}, std::move(noise)), measured_(measured_uv), camera_(camera) {
  if (this->dim() != 2) throw std::invalid_argument("InverseDepthAnchorFactor: noise must be 2-D");
}

bool InverseDepthAnchorFactor::evaluateError(const double* const* x, double* residual,
                                             double** jac) const {
  if (!(x[0][2] > 0.0)) return false;
  Vec2 uv;
  Mat23 J_uv;
  if (!camera_.project(Vec3(x[0][0], x[0][1], 1.0), &uv, jac ? &J_uv : nullptr)) return false;
  Eigen::Map<Vec2> r(residual);
  r = uv - measured_;
  if (jac && jac[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jac[0]);
    J.leftCols<2>() = J_uv.leftCols<2>();
    J.col(2).setZero();
  }
  return true;
}

}  // namespace hdvio
