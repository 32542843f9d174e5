#pragma once
// Pinhole camera with optional radial-tangential distortion (the EuRoC/Kalibr model):
//   x = X/Z, y = Y/Z, r2 = x^2 + y^2
//   x_d = x (1 + k1 r2 + k2 r2^2) + 2 p1 x y + p2 (r2 + 2 x^2)
//   y_d = y (1 + k1 r2 + k2 r2^2) + p1 (r2 + 2 y^2) + 2 p2 x y
//   u = fu x_d + cu,  v = fv y_d + cv      (pixel centres at integer coordinates)
#include <Eigen/Core>

#include "hdvio/core/sequence.h"

namespace hdvio::sim {

class CameraModel {
 public:
  explicit CameraModel(const CameraCalibration& calibration);

  // Distorted pixel of a camera-frame point; false when behind the camera (Z <= 1 cm).
  bool project(const Vec3& p_C, Eigen::Vector2d* uv) const;
  // Ray (x, y, 1) through a pixel (inverse distortion by Gauss-Newton); false if it fails.
  bool unproject(const Eigen::Vector2d& uv, Vec3* ray) const;
  bool inImage(const Eigen::Vector2d& uv) const {
    return uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() <= width() - 1.0 && uv.y() <= height() - 1.0;
  }
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const;

  int width() const { return cal_.width; }
  int height() const { return cal_.height; }
  const CameraCalibration& calibration() const { return cal_; }

 private:
  CameraCalibration cal_;
  double k1_ = 0, k2_ = 0, p1_ = 0, p2_ = 0;
};

}  // namespace hdvio::sim
