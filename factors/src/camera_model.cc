#include "hdvio/factors/camera_model.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "hdvio/core/error.h"

namespace hdvio {

CameraModel::CameraModel(double fu, double fv, double cu, double cv, DistortionModel model,
                         std::vector<double> coefficients, int width, int height)
    : fu_(fu), fv_(fv), cu_(cu), cv_(cv), model_(model), width_(width), height_(height) {
  if (!(fu > 0.0) || !(fv > 0.0) || !std::isfinite(fu) || !std::isfinite(fv) ||
      !std::isfinite(cu) || !std::isfinite(cv))
    throw InputError("", 0, "camera model: focal lengths must be positive and intrinsics finite");
  const std::size_t expected = model == DistortionModel::kNone ? 0 : 4;
  if (coefficients.size() != expected && !(model == DistortionModel::kNone && coefficients.empty()))
    throw InputError("", 0, "camera model: expected " + std::to_string(expected) +
                                " distortion coefficients, got " + std::to_string(coefficients.size()));
  for (std::size_t i = 0; i < coefficients.size(); ++i) {
    if (!std::isfinite(coefficients[i]))
      throw InputError("", 0, "camera model: distortion coefficient is not finite");
    k_[i] = coefficients[i];
  }
}

CameraModel CameraModel::fromCalibration(const CameraCalibration& c) {
  return CameraModel(c.fu, c.fv, c.cu, c.cv, c.distortion, c.distortion_coefficients, c.width,
                     c.height);
}

Vec2 CameraModel::distort(const Vec2& m, Mat2* J) const {
  const double x = m.x(), y = m.y();
  switch (model_) {
    case DistortionModel::kNone:
      if (J) J->setIdentity();
      return m;
    case DistortionModel::kRadialTangential: {
      const double k1 = k_[0], k2 = k_[1], p1 = k_[2], p2 = k_[3];
      const double r2 = x * x + y * y;
      const double radial = 1.0 + r2 * (k1 + k2 * r2);
      const Vec2 md(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                    y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
      if (J) {
        const double dradial = 2.0 * (k1 + 2.0 * k2 * r2);  // d radial / d(x or y), per unit
        (*J)(0, 0) = radial + dradial * x * x + 2.0 * p1 * y + 6.0 * p2 * x;
        (*J)(0, 1) = dradial * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 0) = dradial * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 1) = radial + dradial * y * y + 6.0 * p1 * y + 2.0 * p2 * x;
      }
      return md;
    }
    case DistortionModel::kEquidistant: {
      const double r2 = x * x + y * y;
      if (r2 < 1e-16) {
        if (J) J->setIdentity();
        return m;
      }
      const double r = std::sqrt(r2);
      const double th = std::atan(r);
      const double t2 = th * th;
      const double poly = 1.0 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3])));
      const double thd = th * poly;
      const double scale = thd / r;
      if (J) {
        const double dthd_dth =
            1.0 + t2 * (3.0 * k_[0] + t2 * (5.0 * k_[1] + t2 * (7.0 * k_[2] + t2 * 9.0 * k_[3])));
        const double dthd_dr = dthd_dth / (1.0 + r2);
        const double dscale_dr = (dthd_dr * r - thd) / r2;
        *J = scale * Mat2::Identity() + (dscale_dr / r) * (m * m.transpose());
      }
      return scale * m;
    }
  }
  return m;
}

Vec2 CameraModel::undistort(const Vec2& md) const {
  if (model_ == DistortionModel::kNone) return md;
  Vec2 m = md;
  for (int it = 0; it < 30; ++it) {
    Mat2 J;
    const Vec2 e = distort(m, &J) - md;
    if (e.squaredNorm() < 1e-24) break;
    m -= J.lu().solve(e);
  }
  return m;
}

bool CameraModel::project(const Vec3& p, Vec2* uv, Mat23* J) const {
  if (!(p.z() >= kMinDepth)) return false;
  const double iz = 1.0 / p.z();
  const Vec2 m(p.x() * iz, p.y() * iz);
  Mat2 Jd;
  const Vec2 md = distort(m, J ? &Jd : nullptr);
  *uv = Vec2(fu_ * md.x() + cu_, fv_ * md.y() + cv_);
  if (J) {
    Mat23 Jm;
    Jm << iz, 0.0, -m.x() * iz, 0.0, iz, -m.y() * iz;
    *J = Jd * Jm;
    J->row(0) *= fu_;
    J->row(1) *= fv_;
  }
  return true;
}

Vec3 CameraModel::unproject(const Vec2& uv) const {
  const Vec2 md((uv.x() - cu_) / fu_, (uv.y() - cv_) / fv_);
  const Vec2 m = undistort(md);
  return Vec3(m.x(), m.y(), 1.0).normalized();
}

bool CameraModel::inImage(const Vec2& uv, double border) const {
  return uv.x() >= border && uv.y() >= border && uv.x() <= width_ - 1 - border &&
         uv.y() <= height_ - 1 - border;
}

}  // namespace hdvio
