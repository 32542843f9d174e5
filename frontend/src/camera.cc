#include "hdvio/frontend/camera.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "hdvio/core/error.h"

namespace hdvio::frontend {

Camera::Camera(int width, int height, double fu, double fv, double cu, double cv,
               DistortionModel model, std::vector<double> coefficients)
    : width_(width), height_(height), fu_(fu), fv_(fv), cu_(cu), cv_(cv), model_(model),
      k_(std::move(coefficients)) {
  if (width_ <= 0 || height_ <= 0) throw InputError("", 0, "camera: image size must be positive");
  if (!(fu_ > 0.0) || !(fv_ > 0.0) || !std::isfinite(cu_) || !std::isfinite(cv_))
    throw InputError("", 0, "camera: focal lengths must be positive and finite");
  const std::size_t needed = model_ == DistortionModel::kNone ? 0 : 4;
  if (model_ != DistortionModel::kNone && k_.size() != needed)
    throw InputError("", 0, "camera: distortion needs 4 coefficients, got " +
                                std::to_string(k_.size()));
  for (double k : k_)
    if (!std::isfinite(k)) throw InputError("", 0, "camera: distortion coefficient is not finite");
}

Camera Camera::fromCalibration(const CameraCalibration& c) {
  return Camera(c.width, c.height, c.fu, c.fv, c.cu, c.cv, c.distortion,
                c.distortion_coefficients);
}

Vec2 Camera::distort(const Vec2& xn, Eigen::Matrix2d* J) const {
  const double x = xn.x(), y = xn.y();
  switch (model_) {
    case DistortionModel::kNone:
      if (J) J->setIdentity();
      return xn;
    case DistortionModel::kRadialTangential: {
      const double k1 = k_[0], k2 = k_[1], p1 = k_[2], p2 = k_[3];
      const double r2 = x * x + y * y;
      const double radial = 1.0 + k1 * r2 + k2 * r2 * r2;
      if (J) {
        const double dradial_dr2 = k1 + 2.0 * k2 * r2;
        (*J)(0, 0) = radial + 2.0 * x * x * dradial_dr2 + 2.0 * p1 * y + 6.0 * p2 * x;
        (*J)(0, 1) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 0) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 1) = radial + 2.0 * y * y * dradial_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
      }
      return Vec2(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                  y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
    }
    case DistortionModel::kEquidistant: {
      const double r = std::sqrt(x * x + y * y);
      if (r < 1e-9) {
        if (J) J->setIdentity();
        return xn;
      }
      const double th = std::atan(r), th2 = th * th;
      const double poly = 1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3])));
      const double thd = th * poly;
      const double s = thd / r;
      if (J) {
        const double dthd_dth =
            1.0 + th2 * (3.0 * k_[0] + th2 * (5.0 * k_[1] + th2 * (7.0 * k_[2] + th2 * 9.0 * k_[3])));
        const double dthd_dr = dthd_dth / (1.0 + r * r);
        const double ds_dr = (dthd_dr * r - thd) / (r * r);
        *J = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * xn * xn.transpose();
      }
      return s * xn;
    }
  }
  return xn;
}

Vec2 Camera::undistort(const Vec2& xd) const {
  if (model_ == DistortionModel::kNone) return xd;
  Vec2 x = xd;  // Gauss-Newton on distort(x) = xd, starting at the distorted point
  for (int i = 0; i < 20; ++i) {
    Eigen::Matrix2d J;
    const Vec2 e = distort(x, &J) - xd;
    if (e.squaredNorm() < 1e-22) break;
    x -= J.partialPivLu().solve(e);
  }
  return x;
}

bool Camera::project(const Vec3& p, Vec2* px, Mat23* J) const {
  if (!(p.z() > 1e-9)) return false;
  const double iz = 1.0 / p.z();
  const Vec2 xn(p.x() * iz, p.y() * iz);
  Eigen::Matrix2d Jd;
  const Vec2 xd = distort(xn, J ? &Jd : nullptr);
  *px = Vec2(fu_ * xd.x() + cu_, fv_ * xd.y() + cv_);
  if (J) {
    Mat23 Jn;
    Jn << iz, 0.0, -xn.x() * iz, 0.0, iz, -xn.y() * iz;
    Eigen::Matrix2d K = Eigen::Vector2d(fu_, fv_).asDiagonal();
    *J = K * Jd * Jn;
  }
  return std::isfinite(px->x()) && std::isfinite(px->y());
}

Vec3 Camera::unproject(const Vec2& px) const {
  const Vec2 xn = undistort(Vec2((px.x() - cu_) / fu_, (px.y() - cv_) / fv_));
  return Vec3(xn.x(), xn.y(), 1.0).normalized();
}

bool Camera::isInFrame(const Vec2& px, double border, int level) const {
  const double scale = 1.0 / (1 << level);
  const double u = px.x() * scale, v = px.y() * scale;
  return u >= border && v >= border && u < width_ * scale - border - 1.0 &&
         v < height_ * scale - border - 1.0;
}

}  // namespace hdvio::frontend
