#pragma once
// Keyframe policy (SVO): a new keyframe when the camera has moved away from every keyframe by
// a fraction of the scene depth, or when too few landmarks are still tracked.
#include <vector>

#include "hdvio/frontend/frame.h"

namespace hdvio::frontend {

struct KeyframePolicy {
  double distance = 0.12;   // per unit of median scene depth
  int min_tracked = 70;
  int min_frames_between = 3;
};

bool needNewKeyframe(const Frame& frame, const std::vector<FramePtr>& keyframes,
                     double median_depth, int tracked, int frames_since_keyframe,
                     const KeyframePolicy& policy);

// The keyframe farthest from the frame, to drop when the map is full.
FramePtr farthestKeyframe(const Frame& frame, const std::vector<FramePtr>& keyframes);

// Median and minimum depth of the frame's features that have landmarks; false if none.
bool sceneDepth(const Frame& frame, const Map& map, double* median, double* min);

}  // namespace hdvio::frontend
