#pragma once
// Runs the semi-direct frontend over every image of a sequence, feeding the gyroscope rotation
// prior and, while the frontend bootstraps, the ground-truth pose (standing in for the backend).
#include <functional>
#include <optional>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/frontend/semi_direct_frontend.h"

namespace hdvio::frontend {

struct TrackRunOptions {
  int max_frames = 0;                    // 0: all
  bool gyro_prior = true;
  bool groundtruth_bootstrap = true;     // ground-truth poses while wantsPosePrior()
  FrontendOptions frontend;
};

struct TrackedFrame {
  FrameResult result;
  bool used_groundtruth = false;
  std::optional<Pose> groundtruth_T_WB;  // nearest ground truth within 5 ms, if any
};

struct TrackRunSummary {
  std::vector<TrackedFrame> frames;
  int tracked = 0, lost = 0, reinitializations = 0, keyframes = 0, groundtruth_priors = 0;
  double median_ms = 0, mean_ms = 0, max_ms = 0;  // frontend wall time per image (no image loading)
  double median_cpu_ms = 0, max_cpu_ms = 0;        // thread CPU time per image
  int min_features = 0, median_features = 0;      // over tracked images after the first
};

// Throws InputError if the sequence has no camera or images, or an image cannot be read.
TrackRunSummary runTracking(const Sequence& sequence, const TrackRunOptions& options,
                            const std::function<void(const TrackedFrame&)>& on_frame = {});

}  // namespace hdvio::frontend
