#include "hdvio/core/camera_model.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "hdvio/core/error.h"

namespace hdvio {

CameraModel::CameraModel(int width, int height, double fu, double fv, double cu, double cv,
                         DistortionModel model, std::vector<double> coefficients)
    : width_(width), height_(height), fu_(fu), fv_(fv), cu_(cu), cv_(cv), model_(model) {
  if (width <= 0 || height <= 0)
    throw InputError("", 0, "camera model: image size must be positive, got " +
                                std::to_string(width) + "x" + std::to_string(height));
  if (!(fu > 0.0) || !(fv > 0.0) || !std::isfinite(fu) || !std::isfinite(fv) ||
      !std::isfinite(cu) || !std::isfinite(cv))
    throw InputError("", 0, "camera model: focal lengths must be positive and intrinsics finite");
  const std::size_t expected = model == DistortionModel::kNone ? 0 : 4;
  if (coefficients.size() != expected)
    throw InputError("", 0, "camera model: expected " + std::to_string(expected) +
                                " distortion coefficients, got " + std::to_string(coefficients.size()));
  for (std::size_t i = 0; i < coefficients.size(); ++i) {
    if (!std::isfinite(coefficients[i]))
      throw InputError("", 0, "camera model: distortion coefficient is not finite");
    k_[i] = coefficients[i];
  }
}

CameraModel CameraModel::fromCalibration(const CameraCalibration& c) {
  try {
    return CameraModel(c.width, c.height, c.fu, c.fv, c.cu, c.cv, c.distortion,
                       c.distortion_coefficients);
  } catch (const InputError& e) {
    throw InputError(c.file, 0, e.problem());
  }
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
      const double radial = 1.0 + r2 * (k1 + k2 * r2);  // Horner: one rounding fewer
      const Vec2 md(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                    y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
      if (J) {
        const double dradial = 2.0 * (k1 + 2.0 * k2 * r2);  // d radial / d(x or y), per unit
        (*J)(0, 0) = radial + dradial * x * x + 2.0 * p1 * y + 6.0 * p2 * x;
        (*J)(0, 1) = dradial * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
        (*J)(1, 0) = (*J)(0, 1);
        (*J)(1, 1) = radial + dradial * y * y + 6.0 * p1 * y + 2.0 * p2 * x;
      }
      return md;
    }
    case DistortionModel::kEquidistant: {
      const double r2 = x * x + y * y;
      // Below r = 1e-8, atan(r)/r and the polynomial equal 1 in double: the map is the
      // identity there, and the formulas below would divide by ~0.
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

Vec2 CameraModel::undistort(const Vec2& md, bool* converged) const {
  if (model_ == DistortionModel::kNone) {
    if (converged) *converged = true;
    return md;
  }
  constexpr double kTol2 = kUndistortTolerance * kUndistortTolerance;
  Vec2 m = md;
  for (int it = 0; it < kUndistortMaxIterations; ++it) {
    Mat2 J;
    const Vec2 e = distort(m, &J) - md;
    if (e.squaredNorm() < kTol2) {
      if (converged) *converged = true;
      return m;
    }
    m -= J.partialPivLu().solve(e);
  }
  if (converged) *converged = (distort(m) - md).squaredNorm() < kTol2;
  return m;
}

bool CameraModel::project(const Vec3& p, Vec2* uv, Mat23* J) const {
  if (!(p.z() >= kMinDepth)) return false;  // also rejects a NaN depth
  const double iz = 1.0 / p.z();
  const Vec2 m(p.x() * iz, p.y() * iz);
  Mat2 Jd;
  const Vec2 md = distort(m, J ? &Jd : nullptr);
  const Vec2 pixel(fu_ * md.x() + cu_, fv_ * md.y() + cv_);
  if (!pixel.allFinite()) return false;
  *uv = pixel;
  if (J) {
    Mat23 Jm;
    Jm << iz, 0.0, -m.x() * iz, 0.0, iz, -m.y() * iz;
    *J = Jd * Jm;
    J->row(0) *= fu_;
    J->row(1) *= fv_;
  }
  return true;
}

Vec3 CameraModel::unproject(const Vec2& uv, bool* converged) const {
  const Vec2 md((uv.x() - cu_) / fu_, (uv.y() - cv_) / fv_);
  const Vec2 m = undistort(md, converged);
  return Vec3(m.x(), m.y(), 1.0).normalized();
}

bool CameraModel::inImage(const Vec2& uv, double border, int level) const {
  // Half-open on the far side: the 2x2 bilinear neighbourhood (floor(u) + 1) of every accepted
  // point lies in the level image, so the frontend may interpolate wherever this says yes.
  // The level size is the integer halving of frontend/pyramid.h, not size / 2^L.
  const double scale = std::ldexp(1.0, -level);
  const double u = uv.x() * scale, v = uv.y() * scale;
  return u >= border && v >= border && u < (width_ >> level) - 1.0 - border &&
         v < (height_ >> level) - 1.0 - border;
}

}  // namespace hdvio
