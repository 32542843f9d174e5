#pragma once
// What the visual estimator's image path needs to know: where the backend's landmark
// observations come from and the semi-direct frontend's options plus the frontend-backend
// handshake switches. hdvio_run reads it from the `frontend:` section with
// loadVisualFrontendConfig (visual_frontend_config_loader.h); docs/visual_pipeline.md.
#include "hdvio/frontend/frontend_types.h"

namespace hdvio {

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

}  // namespace hdvio
