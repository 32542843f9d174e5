#pragma once
// Pinhole camera with radial-tangential or equidistant distortion. The frontend never
// undistorts images: it tracks in the raw image and converts pixel positions to bearings.
#include <vector>

#include <Eigen/Core>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"

namespace hdvio::frontend {

using Vec2 = Eigen::Vector2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

class Camera {
 public:
  Camera(int width, int height, double fu, double fv, double cu, double cv,
         DistortionModel model = DistortionModel::kNone, std::vector<double> coefficients = {});
  // Throws InputError if the calibration is unusable (no size, non-positive focal length,
  // wrong number of distortion coefficients).
  static Camera fromCalibration(const CameraCalibration& calibration);

  int width() const { return width_; }
  int height() const { return height_; }
  double focalLength() const { return 0.5 * (fu_ + fv_); }  // pixels per unit-plane unit

  // Camera-frame point -> distorted pixel. False for points behind (or on) the image plane.
  // J (optional) is d(pixel)/d(point).
  bool project(const Vec3& p_c, Vec2* px, Mat23* J = nullptr) const;
  // Distorted pixel -> unit bearing vector in the camera frame.
  Vec3 unproject(const Vec2& px) const;

  // Normalized image plane <-> distorted normalized plane.
  Vec2 distort(const Vec2& xn, Eigen::Matrix2d* J = nullptr) const;
  Vec2 undistort(const Vec2& xd) const;

  bool isInFrame(const Vec2& px, double border = 0.0, int level = 0) const;

 private:
  int width_, height_;
  double fu_, fv_, cu_, cv_;
  DistortionModel model_;
  std::vector<double> k_;
};

}  // namespace hdvio::frontend
