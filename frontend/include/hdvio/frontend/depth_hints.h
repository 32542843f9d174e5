#pragma once
// Initial depths for the corners of a new map from 3-D points another estimator already has
// (the backend's window landmarks after a tracking loss, the visual-inertial initialization's
// triangulated tracks at the start): a map started mid-flight at a fixed prior depth tracks
// with wrong patch warps and projections until its seeds converge.
#include <vector>

#include "hdvio/core/camera_model.h"
#include "hdvio/core/lie.h"

namespace hdvio::frontend {

// Each corner (level-0 pixel) gets the range of the nearest point that projects within
// radius_px of it, else the median range of the points in view, else `fallback`; never less
// than min_depth. T_cw: world to camera.
std::vector<double> hintedDepths(const CameraModel& camera, const Pose& T_cw,
                                 const std::vector<Vec2>& corners_px,
                                 const std::vector<Vec3>& points_W, double radius_px,
                                 double fallback, double min_depth);

}  // namespace hdvio::frontend
