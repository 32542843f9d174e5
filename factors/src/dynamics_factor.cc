#include "hdvio/factors/dynamics_factor.h"

#include <cmath>
#include <stdexcept>

namespace hdvio {
namespace {
using Mat9x6 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;
using Mat9x3 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
}  // namespace

Eigen::Matrix<double, 9, 9> DynamicsFactor::covarianceFor(const PreintegratedThrust& pit,
                                                          const DynamicsFactorParams& params) {
  const double sigma_f = params.variant == DynamicsVariant::kHdvio
                             ? params.force_random_walk * std::sqrt(pit.dt())
                             : params.force_prior_sigma;
  if (!(sigma_f > 0.0) || !std::isfinite(sigma_f))
    throw std::invalid_argument("DynamicsFactor: force sigma must be positive and finite");
  Eigen::Matrix<double, 9, 9> cov = Eigen::Matrix<double, 9, 9>::Zero();
  cov.topLeftCorner<6, 6>() = pit.alphaBetaCovariance();
  cov.bottomRightCorner<3, 3>().diagonal().setConstant(sigma_f * sigma_f);
  return cov;
}

DynamicsFactor::DynamicsFactor(Key pose_i, Key vel_i, Key force_i, Key pose_j, Key vel_j,
                               Key force_j, Key bias_i,
                               std::shared_ptr<const PreintegratedThrust> pit,
                               const DynamicsFactorParams& params)
    : FactorT({pose_i, vel_i, force_i, pose_j, vel_j, force_j, bias_i}, NoiseModel::isotropic(9, 1.0)),
      pit_(std::move(pit)),
      variant_(params.variant),
      drag_(params.drag),
      whitening_(pit_->alphaBetaCovariance(), covarianceFor(*pit_, params).diagonal().tail<3>()) {}

bool DynamicsFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  const PreintegratedThrust& pit = *pit_;
  Eigen::Map<const Vec3> p_i(x[0]), v_i(x[1]), f_i(x[2]), p_j(x[3]), v_j(x[4]), f_j(x[5]);
  Eigen::Map<const Quat> q_i(x[0] + 3);
  Eigen::Map<const Vec6> b_i(x[6]);
  const double dt = pit.dt();
  const Vec3 g_total = pit.params().gravity + f_i;
  const Mat3 Ri = q_i.toRotationMatrix();
  const Mat3 RiT = Ri.transpose();
  const Vec3 dbg = b_i.head<3>() - pit.bias().head<3>();

  const Vec3 y_a = RiT * (p_j - p_i - v_i * dt - 0.5 * dt * dt * g_total);
  const Vec3 y_b = RiT * (v_j - v_i - g_total * dt);
  Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residual);
  r.segment<3>(0) = y_a - (pit.alpha() + pit.dalpha_dbg() * dbg);
  r.segment<3>(3) = y_b - (pit.beta() + pit.dbeta_dbg() * dbg);
  const Vec3 u_i = RiT * v_i, u_j = RiT * v_j;
  const DragIntegral drag = integrateDrag(pit, drag_, u_i, u_j);
  r.segment<3>(0) -= drag.alpha;
  r.segment<3>(3) -= drag.beta;
  Vec3 mean_body = Vec3::Zero();  // kVidFusion: R_i^T f_ext estimated from accel - thrust
  switch (variant_) {
    case DynamicsVariant::kHdvio: r.segment<3>(6) = f_j - f_i; break;
    case DynamicsVariant::kVimo: r.segment<3>(6) = f_i; break;
    case DynamicsVariant::kVidFusion:
      mean_body = pit.correctedGamma(Vec6(b_i)) / dt;
      r.segment<3>(6) = f_i - Ri * mean_body;
      break;
  }
  whitening_.whitenResidual(residual);
  if (!jac) return true;

  if (jac[0]) {  // pose i
    Eigen::Map<Mat9x6> J(jac[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = -RiT;
    J.block<3, 3>(0, 3) = hat(y_a);
    J.block<3, 3>(3, 3) = hat(y_b);
    if (drag_.enabled()) {  // u = R_i^T v: d u / d theta_i = hat(u)
      J.block<3, 3>(0, 3) -= drag.dalpha_dui * hat(u_i) + drag.dalpha_duj * hat(u_j);
      J.block<3, 3>(3, 3) -= drag.dbeta_dui * hat(u_i) + drag.dbeta_duj * hat(u_j);
    }
    if (variant_ == DynamicsVariant::kVidFusion) J.block<3, 3>(6, 3) = Ri * hat(mean_body);
  }
  if (jac[1]) {  // velocity i
    Eigen::Map<Mat9x3> J(jac[1]);
    J.setZero();
    J.block<3, 3>(0, 0) = -dt * RiT - drag.dalpha_dui * RiT;
    J.block<3, 3>(3, 0) = -RiT - drag.dbeta_dui * RiT;
  }
  if (jac[2]) {  // force i
    Eigen::Map<Mat9x3> J(jac[2]);
    J.block<3, 3>(0, 0) = (-0.5 * dt * dt) * RiT;
    J.block<3, 3>(3, 0) = -dt * RiT;
    const double sign = variant_ == DynamicsVariant::kHdvio ? -1.0 : 1.0;
    J.block<3, 3>(6, 0) = sign * Mat3::Identity();
  }
  if (jac[3]) {  // pose j
    Eigen::Map<Mat9x6> J(jac[3]);
    J.setZero();
    J.block<3, 3>(0, 0) = RiT;
  }
  if (jac[4]) {  // velocity j
    Eigen::Map<Mat9x3> J(jac[4]);
    J.setZero();
    J.block<3, 3>(0, 0) = -drag.dalpha_duj * RiT;
    J.block<3, 3>(3, 0) = RiT - drag.dbeta_duj * RiT;
  }
  if (jac[5]) {  // force j
    Eigen::Map<Mat9x3> J(jac[5]);
    J.setZero();
    if (variant_ == DynamicsVariant::kHdvio) J.block<3, 3>(6, 0) = Mat3::Identity();
  }
  if (jac[6]) {  // bias i: [bg, ba]
    Eigen::Map<Mat9x6> J(jac[6]);
    J.setZero();
    J.block<3, 3>(0, 0) = -pit.dalpha_dbg();
    J.block<3, 3>(3, 0) = -pit.dbeta_dbg();
    if (variant_ == DynamicsVariant::kVidFusion) {
      J.block<3, 3>(6, 0) = -Ri * pit.dgamma_dbg() / dt;
      J.block<3, 3>(6, 3) = -Ri * pit.dgamma_dba() / dt;
    }
  }
  const int tangent[7] = {6, 3, 3, 6, 3, 3, 6};
  for (int k = 0; k < 7; ++k) {
    if (!jac[k]) continue;
    if (tangent[k] == 6) whitening_.whitenJacobian<6>(jac[k]);
    else whitening_.whitenJacobian<3>(jac[k]);
  }
  return true;
}

}  // namespace hdvio
