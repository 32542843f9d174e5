#include "hdvio/frontend/keyframe_selection.h"

#include <algorithm>
#include <cmath>

namespace hdvio::frontend {

bool needNewKeyframe(const Frame& frame, const std::vector<FramePtr>& keyframes,
                     double median_depth, int tracked, int frames_since_keyframe,
                     const KeyframePolicy& policy) {
  if (keyframes.empty()) return true;
  if (frames_since_keyframe < policy.min_frames_between) return false;
  if (tracked < policy.min_tracked) return true;
  for (const FramePtr& kf : keyframes) {
    const Vec3 rel = frame.T_cw * kf->cameraCenter();  // keyframe center in the current camera
    if (std::abs(rel.x()) / median_depth < policy.distance &&
        std::abs(rel.y()) / median_depth < policy.distance * 0.8 &&
        std::abs(rel.z()) / median_depth < policy.distance * 1.3)
      return false;
  }
  return true;
}

FramePtr farthestKeyframe(const Frame& frame, const std::vector<FramePtr>& keyframes) {
  FramePtr best;
  double best_d = -1.0;
  const Vec3 c = frame.cameraCenter();
  for (const FramePtr& kf : keyframes) {
    const double d = (kf->cameraCenter() - c).norm();
    if (d > best_d) {
      best_d = d;
      best = kf;
    }
  }
  return best;
}

bool sceneDepth(const Frame& frame, const Map& map, double* median, double* min) {
  std::vector<double> depths;
  for (const Feature& f : frame.features) {
    if (f.landmark_id < 0) continue;
    auto it = map.landmarks.find(f.landmark_id);
    if (it == map.landmarks.end()) continue;
    const double z = (frame.T_cw * it->second->p_w).z();
    if (z > 0.0) depths.push_back(z);
  }
  if (depths.empty()) return false;
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  *median = depths[depths.size() / 2];
  *min = *std::min_element(depths.begin(), depths.end());
  return true;
}

}  // namespace hdvio::frontend
