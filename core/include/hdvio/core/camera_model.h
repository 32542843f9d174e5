#pragma once
// The one pinhole camera of the project (factors, frontend, backend, simulator): radial-
// tangential (k1 k2 p1 p2) or equidistant (Kannala-Brandt, k1..k4) distortion, as in Kalibr /
// EuRoC sensor.yaml. Pixel convention: (0, 0) is the centre of the top-left pixel, u to the
// right, v down; the camera looks along +z. Pyramid level L halves the image L times
// (frontend/pyramid.h): level pixel = pixel / 2^L, level size = size >> L.
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
  // Throws InputError for a non-positive image size or focal length, non-finite intrinsics or
  // coefficients, or a wrong number of coefficients (4 for radtan / equidistant, 0 for none).
  CameraModel(int width, int height, double fu, double fv, double cu, double cv,
              DistortionModel model = DistortionModel::kNone, std::vector<double> coefficients = {});
  // As above; the error names calibration.file.
  static CameraModel fromCalibration(const CameraCalibration& calibration);

  // Camera-frame point -> distorted pixel; d_uv_d_point (2x3) when non-null. False (outputs
  // untouched) when z < kMinDepth or the pixel is not finite.
  bool project(const Vec3& p_C, Vec2* uv, Mat23* d_uv_d_point = nullptr) const;
  // Distorted pixel -> unit bearing (distortion removed by undistort()).
  Vec3 unproject(const Vec2& uv, bool* converged = nullptr) const;

  // Distortion on normalized image coordinates (x/z, y/z) and its 2x2 Jacobian.
  Vec2 distort(const Vec2& m, Mat2* d_md_d_m = nullptr) const;
  // Gauss-Newton inverse of distort(), started at md. *converged (when non-null) tells whether
  // |distort(m) - md| < kUndistortTolerance was reached; it is not where strong distortion
  // folds over (the map is not invertible there).
  Vec2 undistort(const Vec2& md, bool* converged = nullptr) const;

  // Whether a level-0 pixel lies inside the image of pyramid level `level`, `border` level
  // pixels away from its edges.
  bool inImage(const Vec2& uv, double border = 0.0, int level = 0) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double cu() const { return cu_; }
  double cv() const { return cv_; }
  double focalLength() const { return 0.5 * (fu_ + fv_); }  // pixels per unit-plane unit
  DistortionModel distortionModel() const { return model_; }

  // Closer than 1 mm nothing is a landmark a camera here can see or triangulate, and the 1/z
  // Jacobian (f/z > 1e5 px/m) would wreck a Gauss-Newton step: one rule for what the
  // simulator shows, the frontend tracks and the factors accept.
  static constexpr double kMinDepth = 1e-3;  // m
  // Normalized-plane residual of undistort (~1e-9 px at f = 1000 px, far below any pixel
  // noise); Newton converges quadratically, so 30 iterations are only reached when it fails.
  static constexpr double kUndistortTolerance = 1e-12;
  static constexpr int kUndistortMaxIterations = 30;

 private:
  int width_, height_;
  double fu_, fv_, cu_, cv_;
  DistortionModel model_;
  double k_[4] = {0, 0, 0, 0};  // radtan: k1 k2 p1 p2; equidistant: k1 k2 k3 k4
};

}  // namespace hdvio
