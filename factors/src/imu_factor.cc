#include "hdvio/factors/imu_factor.h"

#include <Eigen/Geometry>

namespace hdvio {
namespace {
using Mat15x6 = Eigen::Matrix<double, 15, 6, Eigen::RowMajor>;
using Mat15x3 = Eigen::Matrix<double, 15, 3, Eigen::RowMajor>;
using Mat6R = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Eigen::VectorXd randomWalkSigmas(double dt, const ImuNoiseParams& p) {
  Eigen::VectorXd s(6);
  s.head<3>().setConstant(p.gyro_random_walk * std::sqrt(dt));
  s.tail<3>().setConstant(p.accel_random_walk * std::sqrt(dt));
  return s;
}
}  // namespace

NoiseModelPtr ImuFactor::noiseFor(const PreintegratedImu& pim) {
  const Vec6 random_walk_variances = randomWalkSigmas(pim.dt(), pim.params()).array().square();
  return NoiseModel::blockDiagonal<15, 9>(pim.covariance(), random_walk_variances);
}

ImuFactor::ImuFactor(Key pose_i, Key vel_i, Key bias_i, Key pose_j, Key vel_j, Key bias_j,
                     std::shared_ptr<const PreintegratedImu> pim)
    : FactorT({pose_i, vel_i, bias_i, pose_j, vel_j, bias_j}, noiseFor(*pim)), pim_(std::move(pim)) {}

bool ImuFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  const PreintegratedImu& pim = *pim_;
  Eigen::Map<const Vec3> p_i(x[0]), v_i(x[1]), p_j(x[3]), v_j(x[4]);
  Eigen::Map<const Quat> q_i(x[0] + 3), q_j(x[3] + 3);
  Eigen::Map<const Vec6> b_i(x[2]), b_j(x[5]);
  const double dt = pim.dt();
  const Vec3& g = pim.params().gravity;

  const Vec6 db = b_i - pim.bias();
  const Vec3 dbg = db.head<3>(), dba = db.tail<3>();
  const Vec3 phi_corr = pim.dR_dbg() * dbg;
  const Mat3 dR_corr = pim.deltaR() * so3Exp(phi_corr);
  const Mat3 Ri = q_i.toRotationMatrix(), Rj = q_j.toRotationMatrix();
  const Mat3 RiT = Ri.transpose();
  const Mat3 Rij = RiT * Rj;
  const Mat3 E = dR_corr.transpose() * Rij;
  const Vec3 y_v = RiT * (v_j - v_i - g * dt);
  const Vec3 y_p = RiT * (p_j - p_i - v_i * dt - 0.5 * dt * dt * g);

  Eigen::Map<Eigen::Matrix<double, 15, 1>> r(residual);
  const Vec3 r_R = quatLog(Quat(E));
  r.segment<3>(0) = r_R;
  r.segment<3>(3) = y_v - (pim.deltaV() + pim.dv_dbg() * dbg + pim.dv_dba() * dba);
  r.segment<3>(6) = y_p - (pim.deltaP() + pim.dp_dbg() * dbg + pim.dp_dba() * dba);
  r.segment<6>(9) = b_j - b_i;
  if (!jac) return true;

  const Mat3 JrInv = rightJacobianInverse(r_R);
  if (jac[0]) {  // pose i: [dp, dtheta]
    Eigen::Map<Mat15x6> J(jac[0]);
    J.setZero();
    J.block<3, 3>(0, 3) = -JrInv * Rij.transpose();
    J.block<3, 3>(3, 3) = hat(y_v);
    J.block<3, 3>(6, 0) = -RiT;
    J.block<3, 3>(6, 3) = hat(y_p);
  }
  if (jac[1]) {  // velocity i
    Eigen::Map<Mat15x3> J(jac[1]);
    J.setZero();
    J.block<3, 3>(3, 0) = -RiT;
    J.block<3, 3>(6, 0) = -dt * RiT;
  }
  if (jac[2]) {  // bias i: [bg, ba]
    Eigen::Map<Mat15x6> J(jac[2]);
    J.setZero();
    J.block<3, 3>(0, 0) = -JrInv * E.transpose() * rightJacobian(phi_corr) * pim.dR_dbg();
    J.block<3, 3>(3, 0) = -pim.dv_dbg();
    J.block<3, 3>(3, 3) = -pim.dv_dba();
    J.block<3, 3>(6, 0) = -pim.dp_dbg();
    J.block<3, 3>(6, 3) = -pim.dp_dba();
    J.block<6, 6>(9, 0) = -Mat6R::Identity();
  }
  if (jac[3]) {  // pose j
    Eigen::Map<Mat15x6> J(jac[3]);
    J.setZero();
    J.block<3, 3>(0, 3) = JrInv;
    J.block<3, 3>(6, 0) = RiT;
  }
  if (jac[4]) {  // velocity j
    Eigen::Map<Mat15x3> J(jac[4]);
    J.setZero();
    J.block<3, 3>(3, 0) = RiT;
  }
  if (jac[5]) {  // bias j
    Eigen::Map<Mat15x6> J(jac[5]);
    J.setZero();
    J.block<6, 6>(9, 0) = Mat6R::Identity();
  }
  return true;
}

BiasBetweenFactor::BiasBetweenFactor(Key bias_i, Key bias_j, double dt, const ImuNoiseParams& params)
    : FactorT({bias_i, bias_j}, NoiseModel::diagonal(randomWalkSigmas(dt, params))) {}

bool BiasBetweenFactor::evaluateError(const double* const* x, double* residual, double** jac) const {
  Eigen::Map<const Vec6> b_i(x[0]), b_j(x[1]);
  Eigen::Map<Vec6> r(residual);
  r = b_j - b_i;
  for (int k = 0; k < 2; ++k) {
    if (!jac || !jac[k]) continue;
    Eigen::Map<Mat6R> J(jac[k]);
    J = (k == 0 ? -1.0 : 1.0) * Mat6R::Identity();
  }
  return true;
}

}  // namespace hdvio
