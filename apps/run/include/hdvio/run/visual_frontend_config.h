#pragma once
// The `frontend:` section of a visual experiment (vio, vimo, vid, hdvio): where the backend's
// landmark observations come from and, for images, the semi-direct frontend's options. Strict
// like every config: unknown keys are errors. See docs/visual_pipeline.md.
#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/frontend/frontend_types.h"

namespace hdvio::run {

enum class ObservationSource {
  kAuto,    // tracks when the sequence has landmark tracks (landmarks0/), else images
  kTracks,  // the simulator's ground-truth landmark tracks
  kImages,  // the semi-direct frontend on cam0 images
};

struct VisualFrontendConfig {
  ObservationSource source = ObservationSource::kAuto;
  frontend::FrontendOptions options;
  // The backend's IMU-predicted pose seeds the frontend's sparse alignment (and, while the
  // frontend bootstraps or relocalizes, is the image pose).
  bool backend_pose_prior = true;
  // Optimized keyframe poses and landmarks go back into the frontend's map after every frame.
  bool backend_feedback = true;
  // Frames with fewer tracked features are given to the backend without observations
  // (IMU-only step) and counted as lost.
  int min_features_for_backend = 10;
};

VisualFrontendConfig loadVisualFrontendConfig(const ConfigReader& section);

// kTracks or kImages for this sequence; throws InputError when the sequence lacks what the
// chosen source needs (tracks, or a camera with images).
ObservationSource resolveObservationSource(ObservationSource configured, const Sequence& seq);

}  // namespace hdvio::run
