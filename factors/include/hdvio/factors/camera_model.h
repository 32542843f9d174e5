#pragma once
// Pinhole camera with radial-tangential (k1 k2 p1 p2) or equidistant (Kannala-Brandt, k1..k4)
// distortion, as in Kalibr / EuRoC sensor.yaml. Pixel convention: (0, 0) is the centre of the
// top-left pixel, u to the right, v down; the camera looks along +z.
// Shared by the factors and, later, the frontend (kept free of Ceres).
#include <vector>

#include <Eigen/Core>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"

namespace hdvio {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

class CameraModel {
 public:
  // Throws InputError for non-positive focal lengths or a wrong number of coefficients.
  CameraModel(double fu, double fv, double cu, double cv, DistortionModel model,
              std::vector<double> coefficients, int width = 0, int height = 0);
  static CameraModel fromCalibration(const CameraCalibration& calib);

  // Projects a point in camera coordinates; false (outputs untouched) if z < kMinDepth.
  // d_uv_d_point (2x3) is filled when non-null.
  bool project(const Vec3& p_C, Vec2* uv, Mat23* d_uv_d_point = nullptr) const;
  // Unit bearing vector of a pixel (distortion removed iteratively).
  Vec3 unproject(const Vec2& uv) const;

  // Distortion on normalized image coordinates (x/z, y/z) and its 2x2 Jacobian.
  Vec2 distort(const Vec2& m, Mat2* d_md_d_m = nullptr) const;
  Vec2 undistort(const Vec2& md) const;  // Gauss-Newton inverse of distort

  bool inImage(const Vec2& uv, double border = 0.0) const;
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double cu() const { return cu_; }
  double cv() const { return cv_; }
  int width() const { return width_; }
  int height() const { return height_; }
  DistortionModel distortionModel() const { return model_; }

  static constexpr double kMinDepth = 1e-3;  // m

 private:
  double fu_, fv_, cu_, cv_;
  DistortionModel model_;
  double k_[4] = {0, 0, 0, 0};  // radtan: k1 k2 p1 p2; equidistant: k1 k2 k3 k4
  int width_, height_;
};

}  // namespace hdvio
