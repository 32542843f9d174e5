#include "hdvio/factors/reprojection_factor.h"

#include <stdexcept>

namespace hdvio {

NoiseModelPtr pixelNoise(double sigma_px, RobustLoss loss, double loss_width_px) {
  NoiseModelPtr base = NoiseModel::isotropic(2, sigma_px);
  // The loss acts on the whitened residual, so its width is expressed in sigmas.
  const double width = loss_width_px / sigma_px;
  switch (loss) {
    case RobustLoss::kNone: return base;
    case RobustLoss::kHuber: return base->robust(std::make_shared<ceres::HuberLoss>(width));
  }
  return base;
}

ReprojectionFactor::ReprojectionFactor(Key pose, Key landmark, const Vec2& measured_uv,
                                       const CameraModel& camera, const Pose& T_BC,
                                       NoiseModelPtr noise)
    : FactorT({pose, landmark}, std::move(noise)), measured_(measured_uv), camera_(camera) {
  if (this->dim() != 2) throw std::invalid_argument("ReprojectionFactor: noise must be 2-D");
  const Pose T_CB = T_BC.inverse();
  R_CB_ = T_CB.R();
  t_CB_ = T_CB.p;
}

bool ReprojectionFactor::evaluateError(const double* const* x, double* residual,
                                       double** jac) const {
  Eigen::Map<const Vec3> p_WB(x[0]), l_W(x[1]);
  Eigen::Map<const Quat> q_WB(x[0] + 3);
  const Mat3 R_BW = q_WB.toRotationMatrix().transpose();
  const Vec3 l_B = R_BW * (l_W - p_WB);
  const Vec3 p_C = R_CB_ * l_B + t_CB_;
  Vec2 uv;
  Mat23 J_uv;
  if (!camera_.project(p_C, &uv, jac ? &J_uv : nullptr)) return false;
  Eigen::Map<Vec2> r(residual);
  r = uv - measured_;
  if (!jac) return true;
  const Mat23 J_B = J_uv * R_CB_;  // d uv / d l_B
  if (jac[0]) {  // pose: d l_B / d p = -R_BW, d l_B / d theta = [l_B]x
    Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J(jac[0]);
    J.leftCols<3>() = -J_B * R_BW;
    J.rightCols<3>() = J_B * hat(l_B);
  }
  if (jac[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jac[1]);
    J = J_B * R_BW;
  }
  return true;
}

}  // namespace hdvio
