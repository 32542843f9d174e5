#pragma once
// The landmark observations of one image: what a frontend (or the simulator's tracks) hands to
// the visual backend and to the visual-inertial initialization.
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio {

struct FeatureObservation {
  int landmark_id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // distorted pixel coordinates (Vec2)
};

struct FrameObservations {
  Timestamp t = 0;
  std::vector<FeatureObservation> features;
};

}  // namespace hdvio
