#include "hdvio/factors/point_mass_dynamics.h"

#include <cmath>
#include <stdexcept>

namespace hdvio {
namespace {
using Mat9x6 = Eigen::Matrix<double, 9, 6, Eigen::RowMajor>;
using Mat9x3 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
}  // namespace

PointMassDynamics::PointMassDynamics(std::shared_ptr<const PreintegratedThrust> pit,
                                     const DragLaw& drag)
    : pit_(std::move(pit)), drag_(drag) {}

std::shared_ptr<const NoiseModel> PointMassDynamics::noiseFor(const PreintegratedThrust& pit,
                                                             const DynamicsFactorParams& params,
                                                             double sigma_f) {
  if (!(sigma_f > 0.0) || !std::isfinite(sigma_f))
    throw std::invalid_argument("dynamics factor: force sigma must be positive and finite");
  return NoiseModel::blockDiagonal<9, 6>(
      pit.alphaBetaCovariance() +
          dragCovariance(pit, params.drag, params.sigma_velocity_i, params.sigma_velocity_j),
      Vec3::Constant(sigma_f * sigma_f));
}

Mat3 PointMassDynamics::evaluate(const Inputs& x, double* residual, const Jacobians* jac) const {
  const PreintegratedThrust& pit = *pit_;
  Eigen::Map<const Vec3> p_i(x.pose_i), v_i(x.vel_i), f_i(x.force_i), p_j(x.pose_j), v_j(x.vel_j);
  Eigen::Map<const Quat> q_i(x.pose_i + 3);
  Eigen::Map<const Vec6> b_i(x.bias_i);
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
  if (!jac) return Ri;

  if (jac->pose_i) {
    Eigen::Map<Mat9x6> J(jac->pose_i);
    J.setZero();
    J.block<3, 3>(0, 0) = -RiT;
    J.block<3, 3>(0, 3) = hat(y_a);
    J.block<3, 3>(3, 3) = hat(y_b);
    if (drag_.enabled()) {  // u = R_i^T v: d u / d theta_i = hat(u)
      J.block<3, 3>(0, 3) -= drag.dalpha_dui * hat(u_i) + drag.dalpha_duj * hat(u_j);
      J.block<3, 3>(3, 3) -= drag.dbeta_dui * hat(u_i) + drag.dbeta_duj * hat(u_j);
    }
  }
  if (jac->vel_i) {
    Eigen::Map<Mat9x3> J(jac->vel_i);
    J.setZero();
    J.block<3, 3>(0, 0) = -dt * RiT - drag.dalpha_dui * RiT;
    J.block<3, 3>(3, 0) = -RiT - drag.dbeta_dui * RiT;
  }
  if (jac->force_i) {
    Eigen::Map<Mat9x3> J(jac->force_i);
    J.block<3, 3>(0, 0) = (-0.5 * dt * dt) * RiT;
    J.block<3, 3>(3, 0) = -dt * RiT;
  }
  if (jac->pose_j) {
    Eigen::Map<Mat9x6> J(jac->pose_j);
    J.setZero();
    J.block<3, 3>(0, 0) = RiT;
  }
  if (jac->vel_j) {
    Eigen::Map<Mat9x3> J(jac->vel_j);
    J.setZero();
    J.block<3, 3>(0, 0) = -drag.dalpha_duj * RiT;
    J.block<3, 3>(3, 0) = RiT - drag.dbeta_duj * RiT;
  }
  if (jac->bias_i) {  // [bg, ba]
    Eigen::Map<Mat9x6> J(jac->bias_i);
    J.setZero();
    J.block<3, 3>(0, 0) = -pit.dalpha_dbg();
    J.block<3, 3>(3, 0) = -pit.dbeta_dbg();
  }
  return Ri;
}

}  // namespace hdvio
