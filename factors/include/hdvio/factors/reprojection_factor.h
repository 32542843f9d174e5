#pragma once
// Reprojection of a world-frame landmark L_j (Vec3Var, xyz in metres) into the camera of pose
// X_k = T_WB: r = project(T_CB T_WB^-1 l) - z, 2-D in pixels. T_BC (camera -> body, the
// sensor.yaml T_BS) is fixed. Returns false (invalid evaluation) when the point is closer than
// CameraModel::kMinDepth in front of the camera; add only observations with positive depth.
// Noise: isotropic pixel sigma, optionally with a Huber loss (pixelNoise()).
#include <memory>

#include "hdvio/core/factor.h"
#include "hdvio/core/camera_model.h"

namespace hdvio {

enum class RobustLoss { kNone, kHuber };

// Isotropic 2-D pixel noise; with a loss, its scale is loss_width_px (in pixels).
NoiseModelPtr pixelNoise(double sigma_px, RobustLoss loss = RobustLoss::kNone,
                         double loss_width_px = 1.0);

class ReprojectionFactor final : public FactorT<ReprojectionFactor, 2, PoseVar, Vec3Var> {
 public:
  ReprojectionFactor(Key pose, Key landmark, const Vec2& measured_uv, const CameraModel& camera,
                     const Pose& T_BC, NoiseModelPtr noise);

  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const Vec2& measured() const { return measured_; }

 private:
  Vec2 measured_;
  CameraModel camera_;
  Mat3 R_CB_;
  Vec3 t_CB_;
};

}  // namespace hdvio
