#pragma once
// Relative position between two poses, e.g. a learned displacement (IMO / TLIO style):
//   r = p_j - p_i - d,   3-D,  d expressed in the WORLD frame (gravity-aligned, z up, with the
// world yaw), which is the frame the learned inertial odometry network predicts in. The
// network's covariance becomes the noise model (NoiseModel::covariance).
#include "hdvio/core/factor.h"

namespace hdvio {

class RelativePositionFactor final : public FactorT<RelativePositionFactor, 3, PoseVar, PoseVar> {
 public:
  RelativePositionFactor(Key pose_i, Key pose_j, const Vec3& displacement_W, NoiseModelPtr noise);
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const Vec3& displacement() const { return d_; }

 private:
  Vec3 d_;
};

}  // namespace hdvio
