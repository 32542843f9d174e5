#pragma once
// Reprojection of known race-gate corners for the IMO filter's evolving state (docs/gate_io.md).
// A corner X (world) is seen by the camera at
//   p_B = R^T (X - p),   p_C = R_BC^T (p_B - t_BC),   uv = pi(p_C)
// with the body pose (R, p), the camera extrinsics T_BC (camera -> body) and pi the camera
// model (distortion included). The residual is uv_observed - pi(p_C), two rows per corner,
// stacked per frame; the Jacobian of pi(p_C) is taken with respect to the error state's
// dtheta (right perturbation, R Exp(dtheta)) and dp (additive, world).
#include <vector>

#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/core/camera_model.h"

namespace hdvio::imo {

struct GateCornerObservation {
  Vec3 corner_W = Vec3::Zero();  // known corner position (world)
  Vec2 uv = Vec2::Zero();        // detected pixel (distorted)
};

// Predicted pixel of corner_W and d(uv)/d[dtheta, dp] (2 x 6). False when the corner is
// closer than CameraModel::kMinDepth in front of the camera (outputs untouched).
bool projectGateCorner(const CameraModel& camera, const Pose& T_BC, const Mat3& R, const Vec3& p,
                       const Vec3& corner_W, Vec2* uv, Eigen::Matrix<double, 2, 6>* J = nullptr);

struct GateFrameMeasurement {
  VecX residual;          // 2 k: observed - predicted, corners in the order of `used`
  MatX H;                 // 2 k x state_dim, nonzero only in the evolving dtheta and dp columns
  std::vector<int> used;  // indices into the observations (corners in front of the camera)
};

// Stacks the corners of one frame for ImoFilter::updateGeneric; state_dim = 15 + 9 N.
GateFrameMeasurement gateFrameMeasurement(const CameraModel& camera, const Pose& T_BC,
                                          const ImoNominalState& x,
                                          const std::vector<GateCornerObservation>& observations,
                                          int state_dim);

}  // namespace hdvio::imo
