#include "hdvio/core/manifolds.h"

#include <Eigen/Core>

#include "hdvio/core/lie.h"

namespace hdvio {
namespace {
using RowMat67 = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;
using RowMat76 = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Map<const Vec3> p(x);
  Eigen::Map<const Quat> q(x + 3);
  Eigen::Map<const Vec3> dp(delta);
  Eigen::Map<const Vec3> dtheta(delta + 3);
  Eigen::Map<Vec3> p_out(x_plus_delta);
  Eigen::Map<Quat> q_out(x_plus_delta + 3);
  p_out = p + dp;
  q_out = (q * quatExp(dtheta)).normalized();
  return true;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMat76> J(jacobian);
  const double w = x[6];
  const Vec3 v(x[3], x[4], x[5]);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  // d(q * [dtheta/2, 1]) / d(dtheta) at 0, rows ordered x, y, z, w.
  J.block<3, 3>(3, 3) = 0.5 * (w * Mat3::Identity() + hat(v));
  J.block<1, 3>(6, 3) = -0.5 * v.transpose();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<const Vec3> py(y), px(x);
  Eigen::Map<const Quat> qy(y + 3), qx(x + 3);
  Eigen::Map<Vec3> dp(y_minus_x), dtheta(y_minus_x + 3);
  dp = py - px;
  dtheta = quatLog(qx.conjugate() * qy);
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  liftJacobian(x, jacobian);
  return true;
}

void PoseManifold::liftJacobian(const double* x, double* jacobian) {
  Eigen::Map<RowMat67> J(jacobian);
  const double w = x[6];
  const Vec3 v(x[3], x[4], x[5]);
  J.setZero();
  J.topLeftCorner<3, 3>().setIdentity();
  // d Log(q^-1 * y) / dy at y = q equals 2 * vec-rows of the left product by q^-1.
  J.block<3, 3>(3, 3) = 2.0 * (w * Mat3::Identity() - hat(v));
  J.block<3, 1>(3, 6) = -2.0 * v;
}

std::shared_ptr<ceres::Manifold> poseManifold() {
  static const std::shared_ptr<ceres::Manifold> instance = std::make_shared<PoseManifold>();
  return instance;
}

}  // namespace hdvio
