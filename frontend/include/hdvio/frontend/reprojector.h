#pragma once
// Projects the map's landmarks into a frame whose pose has been aligned, keeps at most one
// candidate per grid cell (converged landmarks first) and refines each by feature alignment
// against the keyframe that saw it from the most similar direction.
#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/frame.h"

namespace hdvio::frontend {

struct ReprojectionStats {
  int candidates = 0;  // landmarks projecting into the image
  int matched = 0;     // features added to the frame
  int failed = 0;      // alignments that failed
};

// A landmark whose depth is still a seed's guess (not converged) projects several pixels off:
// it is searched on this level or coarser, and the pose optimization weighs it as a
// measurement of this level.
constexpr int kUnconvergedLevel = 2;

// Appends one Feature (with landmark_id) per matched landmark to frame->features: aligned on the
// level that matches the patch's scale (at least kUnconvergedLevel for an unconverged landmark),
// then refined down to level 0 (refineToFinerLevels); Feature::level is the finest level reached.
ReprojectionStats reprojectMap(const CameraModel& camera, const FeatureGrid& grid, int max_features,
                               int landmark_max_failures, Map* map, Frame* frame);

}  // namespace hdvio::frontend
