#pragma once
// A visual backend (vio, vimo, vid, hdvio) on camera images: the semi-direct frontend tracks
// every image and hands its landmark observations to the sliding-window backend, which in turn
// gives the frontend its IMU-predicted pose as prior and its optimized keyframes and landmarks
// back (so the frontend's map stays metric). Deterministic: one image at a time, frontend then
// backend; only PNG decoding runs ahead on one I/O thread (io::ImagePrefetcher).
//
// Start: VioStarter (backend/vio_starter.h) as on landmark tracks. Until it decides, images go
// to a KLT tracker (init_feature_tracker.h) whose tracks feed the visual-inertial
// initialization; the frontend then starts its map on the image of the first state, at that
// metric, gravity-aligned pose (its usual start / re-initialization path).
//
// Degradation: an image the frontend cannot track (or with too few features) becomes an
// IMU-only (and dynamics) step of the backend; the frontend relocalizes and, after a while,
// re-initializes its map at the backend's pose. Every such image is counted and logged.
#include <string>
#include <vector>

#include "hdvio/backend/vio_runner.h"
#include "hdvio/frontend/frontend_types.h"
#include "hdvio/run/visual_frontend_config.h"

namespace hdvio::run {

// What happened to one image, for logs and tests.
struct ImageFrameRecord {
  Timestamp t = 0;
  frontend::TrackingStage stage = frontend::TrackingStage::kInitializing;
  bool tracked = false;
  bool reinitialized = false;
  bool used_by_backend = false;  // observations were given to the backend
  int tracked_features = 0;
  int frontend_keyframe = 0;     // 1 when the frontend took a keyframe
  double frontend_ms = 0.0;      // wall time of SemiDirectFrontend::track
  double load_ms = 0.0;          // waiting for the I/O thread's decoded image
};

struct ImageRunOutput {
  VioRunOutput vio;                     // states and backend results, one per processed frame
  std::vector<ImageFrameRecord> images; // one per image the frontend saw
  double frontend_time_s = 0.0;
  double load_time_s = 0.0;
  int lost_images = 0;                  // not tracked or too few features: IMU-only steps
  int reinitializations = 0;
  // Before the first state (vio.start says how it came): images given to the initialization
  // tracker, and the wall time of that tracking plus the VI initialization attempts.
  int init_images = 0;
  double init_time_s = 0.0;
};

// Throws InputError when the sequence lacks a camera, images, IMU or (dynamics methods) thrust,
// or an image cannot be read. `log`: print lost-tracking episodes and a summary on stderr.
ImageRunOutput runVioOnImages(const Sequence& seq, const VioBackendOptions& backend_options,
                              const VioRunOptions& run, const VisualFrontendConfig& frontend,
                              ResidualForceSource residual_force = nullptr, bool log = true);

}  // namespace hdvio::run
