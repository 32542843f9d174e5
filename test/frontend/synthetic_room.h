#pragma once
// A textured box room rendered by ray casting, for tests with exactly known geometry.
#include <opencv2/core.hpp>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/camera_model.h"

namespace hdvio::frontend::test {

// Room [-5, 5] x [-5, 5] x [0, 3] m; every wall carries smooth value-noise texture with
// blobs that FAST responds to.
class SyntheticRoom {
 public:
  explicit SyntheticRoom(unsigned seed = 7);
  // Distance along the ray from the camera center to the first wall; the ray is in world frame.
  double castRay(const Vec3& origin, const Vec3& dir, Vec3* hit) const;
  double intensity(const Vec3& p_w) const;  // 0..255
  cv::Mat render(const CameraModel& camera, const Pose& T_wc) const;
  // Depth (camera z) of the scene at a pixel.
  double depthAt(const CameraModel& camera, const Pose& T_wc, const Vec2& px) const;

 private:
  double noise(double u, double v, int octave) const;
  unsigned seed_;
};

// EuRoC-like 752x480 camera with mild radial-tangential distortion.
CameraCalibration syntheticCalibration();
// Camera looking along +x from (x, y, z), yawed by yaw and pitched down by pitch (rad).
Pose lookingForward(const Vec3& position, double yaw, double pitch);

}  // namespace hdvio::frontend::test
