#pragma once
// Observations of a landmark anchored in the camera of pose X_a with inverse depth
// lambda = (alpha, beta, rho) (a 3-D VectorVar): the landmark is (alpha, beta, 1) / rho in the
// anchor camera, i.e. the anchor's normalized image point at depth 1/rho (the anchored
// inverse depth of Civera et al. and OpenVINS). Observed from pose X_k (k != a):
//   h = rho * p_Ck = R_CB R_WBk^T (R_WBa (R_BC m + rho t_BC) + rho (p_a - p_k)) + rho t_CB,
//   m = (alpha, beta, 1),  r = project(h) - z   (pixels; a central projection is scale invariant).
// Multiplying by rho keeps the residual smooth up to points at infinity (rho = 0), where the
// landmark still constrains the relative rotation: the reason for this parameterization over
// world points, which need parallax before they can enter. The anchor's own observation is
// InverseDepthAnchorFactor (r = project(m) - z), so every observation counts.
// Invalid (returns false) when rho <= 0 or the point is closer than CameraModel::kMinDepth in
// front of the observing camera.
#include "hdvio/core/camera_model.h"
#include "hdvio/core/factor.h"

namespace hdvio {

using InverseDepthVar = VectorVar<3>;

// The landmark of an anchored inverse depth, and back (p_Ca.z() > 0).
Vec3 inverseDepthWorldPoint(const Pose& T_WBa, const Pose& T_BC, const Vec3& lambda);
Vec3 inverseDepthFromAnchorPoint(const Vec3& p_Ca);

class InverseDepthReprojectionFactor final
    : public FactorT<InverseDepthReprojectionFactor, 2, PoseVar, PoseVar, InverseDepthVar> {
 public:
  InverseDepthReprojectionFactor(Key anchor_pose, Key pose, Key inverse_depth,
                                 const Vec2& measured_uv, const CameraModel& camera,
                                 const Pose& T_BC, NoiseModelPtr noise);

  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const Vec2& measured() const { return measured_; }

 private:
  Vec2 measured_;
  CameraModel camera_;
  Mat3 R_BC_;
  Vec3 t_BC_;
  Mat3 R_CB_;
  Vec3 t_CB_;
};

// The anchor camera's own observation: it constrains (alpha, beta), not the depth.
class InverseDepthAnchorFactor final
    : public FactorT<InverseDepthAnchorFactor, 2, InverseDepthVar> {
 public:
  InverseDepthAnchorFactor(Key inverse_depth, const Vec2& measured_uv, const CameraModel& camera,
                           NoiseModelPtr noise);

  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const Vec2& measured() const { return measured_; }

 private:
  Vec2 measured_;
  CameraModel camera_;
};

}  // namespace hdvio
