#pragma once
// Feeds a whole recorded or simulated sequence through a VisualEstimator in time order (IMU and
// thrust up to each frame, then the frame): on the simulator's ground-truth landmark tracks
// (optionally with added pixel noise) or on cam0 images (decoded one I/O thread ahead,
// io::ImagePrefetcher). This is all hdvio_run does with a visual method besides configuration
// and result writing; a live program would feed the estimator itself.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/pipeline/visual_estimator.h"

namespace hdvio {

struct VioRunOutput {
  std::vector<NavState> states;       // one per processed frame, latest estimate at that time
  std::vector<FrameResult> frames;
  double backend_time_s = 0.0;        // wall time spent in the backend
  bool visual_inertial_start = false;  // the first state came from the VI initialization
  StartKind start = StartKind::kNone;
  Timestamp start_t = 0;               // time of the first state
  int vi_init_attempts = 0;
  ViInitResult vi_init;                // the VI initialization's last attempt (if any)
  std::vector<Vec3> model_force_B;     // VisualEstimator::modelForceAt each state, if it has one
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

// Frames of landmark observations grouped by timestamp (simulated sequences).
std::vector<FrameObservations> framesFromTracks(const Sequence& seq, double pixel_noise_sigma,
                                                std::uint32_t seed);

// The image plus Gaussian noise of sigma gray levels (rounded, saturated), drawn from OpenCV's
// own generator seeded by (seed, t): the same on every machine and independent of the order
// in which images are decoded.
cv::Mat withImageNoise(const cv::Mat& gray, double sigma, std::uint32_t seed, Timestamp t);

// Throws InputError when the sequence lacks a camera, IMU, tracks or (dynamics methods) thrust,
// or no first state could be decided.
VioRunOutput runVioOnTracks(const Sequence& seq, const VioBackendOptions& options,
                            const VioRunOptions& run,
                            std::shared_ptr<const learned::ResidualForceProvider> residual_force = nullptr);
// The same on given frames of observations (e.g. framesFromTracks with levels or noise of a
// test's choosing); run.pixel_noise_sigma is not applied again.
VioRunOutput runVioOnFrames(const Sequence& seq, const std::vector<FrameObservations>& frames,
                            const VioBackendOptions& options, const VioRunOptions& run,
                            std::shared_ptr<const learned::ResidualForceProvider> residual_force = nullptr);

// Also throws InputError when the sequence has no images or an image cannot be read. `log`:
// print the start, lost-tracking episodes and a summary on stderr. on_image (may be empty):
// called with each image time (progress display). on_step (may be empty): called with the
// estimator's answer for each image after the start (diagnostics).
ImageRunOutput runVioOnImages(const Sequence& seq, const VioBackendOptions& backend_options,
                              const VioRunOptions& run, const VisualFrontendConfig& frontend,
                              std::shared_ptr<const learned::ResidualForceProvider> residual_force = nullptr,
                              bool log = true, const std::function<void(Timestamp)>& on_image = {},
                              const std::function<void(const ImageStep&)>& on_step = {});

}  // namespace hdvio
