#include "hdvio/sim/camera_model.h"

#include <Eigen/Dense>

namespace hdvio::sim {

CameraModel::CameraModel(const CameraCalibration& calibration) : cal_(calibration) {
  if (cal_.distortion == DistortionModel::kRadialTangential && cal_.distortion_coefficients.size() == 4) {
    k1_ = cal_.distortion_coefficients[0];
    k2_ = cal_.distortion_coefficients[1];
    p1_ = cal_.distortion_coefficients[2];
    p2_ = cal_.distortion_coefficients[3];
  }
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y(), r2 = x * x + y * y;
  const double radial = 1.0 + k1_ * r2 + k2_ * r2 * r2;
  return Eigen::Vector2d(x * radial + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x),
                         y * radial + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y);
}

bool CameraModel::project(const Vec3& p_C, Eigen::Vector2d* uv) const {
  if (p_C.z() <= 0.01) return false;
  const Eigen::Vector2d d = distort(Eigen::Vector2d(p_C.x() / p_C.z(), p_C.y() / p_C.z()));
  *uv = Eigen::Vector2d(cal_.fu * d.x() + cal_.cu, cal_.fv * d.y() + cal_.cv);
  return true;
}

bool CameraModel::unproject(const Eigen::Vector2d& uv, Vec3* ray) const {
  const Eigen::Vector2d target((uv.x() - cal_.cu) / cal_.fu, (uv.y() - cal_.cv) / cal_.fv);
  Eigen::Vector2d xy = target;
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector2d r = distort(xy) - target;
    if (r.norm() < 1e-14) break;
    // Numeric Jacobian is plenty accurate for this smooth map.
    Eigen::Matrix2d J;
    const double h = 1e-7;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d e = xy;
      e[k] += h;
      J.col(k) = (distort(e) - distort(xy)) / h;
    }
    xy -= J.inverse() * r;
  }
  if ((distort(xy) - target).norm() > 1e-9) return false;
  *ray = Vec3(xy.x(), xy.y(), 1.0);
  return true;
}

}  // namespace hdvio::sim
