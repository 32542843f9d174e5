#pragma once
// Pixel detections of race-gate corners, as a gate detector would report them (docs/gate_io.md):
// per camera frame, the four inner corners of the front face of every gate (the face the flight
// approaches) that are in front of the camera, within max_distance, inside the image, not folded
// by the distortion and not hidden by any gate frame, with pixel noise and random dropouts.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "hdvio/core/camera_model.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/sim/scene.h"
#include "hdvio/sim/sim_config.h"

namespace hdvio::sim {

// World positions of a gate's inner front-face corners in the order of gates0/gates.csv:
// seen along the flight direction, 0 top-left, 1 top-right, 2 bottom-right, 3 bottom-left.
std::array<Vec3, io::kCornersPerGate> gateCornersWorld(const Gate& gate);

// Whether the straight line from the camera centre reaches corner `corner_id` of `gate`
// (tested on a probe 1 cm inside the opening and 1 mm in front of the face, so the corner's
// own frame only hides it when a bar is really in the way).
bool gateCornerVisible(const Scene& scene, const Gate& gate, int corner_id, const Vec3& camera_center);

// Whether pixel uv, the projection of the camera-frame point p_C, undistorts back to p_C's ray
// (within 1e-6 on the z = 1 plane): strong distortion folds far-off-axis points into the
// image, and such a point is not seen there. Used for landmark tracks and gate corners.
bool mapsBackToRay(const CameraModel& camera, const Eigen::Vector2d& uv, const Vec3& p_C);

// Map of every gate of the scene and the detections in the frames (timestamp, T_WC), in time
// order; deterministic for a seed.
io::GateData detectGateCorners(const Scene& scene, const CameraModel& camera,
                               const GateDetectionConfig& config,
                               const std::vector<std::pair<Timestamp, Pose>>& frames,
                               std::uint64_t seed);

}  // namespace hdvio::sim
