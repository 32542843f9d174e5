#pragma once
// Ray-casting renderer: per pixel, the precomputed camera ray (distortion included) is rotated
// into the world, intersected with the room box (and gates), and the face texture is sampled
// trilinearly from its mip pyramid at the level matching the pixel footprint.
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/core/camera_model.h"
#include "hdvio/sim/scene.h"

namespace hdvio::sim {

class Renderer {
 public:
  Renderer(const Scene& scene, const CameraModel& camera);

  // Gray levels as CV_32F (unclamped); depth (camera z, m) as CV_32F if requested.
  // Throws InputError if the camera is outside the room.
  void render(const Pose& T_WC, cv::Mat* image, cv::Mat* depth = nullptr) const;

 private:
  float sampleFace(int face, double u, double v, double footprint) const;

  const Scene& scene_;
  const CameraModel& camera_;
  std::vector<Vec3> rays_;  // (x, y, 1) per pixel, row-major
  double focal_;            // for the footprint estimate
};

}  // namespace hdvio::sim
