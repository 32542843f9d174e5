#pragma once
// How a visual-inertial estimator gets its first state, on landmark tracks and on images alike:
// ground truth when asked for, else the visual-inertial initialization over a window of frames
// (moving start), the static initialization when the camera sees no parallax and the IMU is
// still (start at rest), and the static guess after a timeout whatever the motion. Feed every
// frame until addFrame() returns a state; the estimator then initializes its backend (and
// frontend) with it. Part of VisualEstimator (visual_estimator.h); tests use it alone.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hdvio/backend/vi_initialization.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/core/sequence.h"

namespace hdvio {

struct VioRunOptions {
  bool init_from_groundtruth = false;  // else: visual-inertial initialization (below)
  // Visual-inertial initialization (vi_initialization.h) over this window; while the camera
  // sees no parallax and the IMU says the vehicle is still, the static initialization is used
  // instead. false: static (hover) initialization only, as for a start at rest.
  bool visual_inertial_init = true;
  double vi_init_window_s = 2.0;
  double vi_init_timeout_s = 5.0;  // then the static guess, whatever the motion
  double static_init_window_s = 0.5;
  double guess_velocity_sigma = 1.0;  // prior sigmas of the guessed first state (m/s, rad)
  double guess_tilt_sigma = 0.1;
  double pixel_noise_sigma = 0.0;      // added to simulated tracks (visual_sequence_runner.h)
  // Gaussian noise (gray levels) added to every decoded camera image, from (seed, timestamp):
  // runs on images differ by seed, so a result can be judged over several seeds of one flight.
  double image_noise_sigma = 0.0;
  std::uint32_t seed = 1;
};

// Where the first state came from.
enum class StartKind {
  kNone,             // not started (yet)
  kGroundTruth,      // run.init_from_groundtruth
  kVisualInertial,   // the visual-inertial initialization succeeded
  kStatic,           // static initialization: visual_inertial_init off
  kStaticAtRest,     // no parallax and a still IMU: the static initialization is valid
  kStaticTimeout,    // the VI initialization kept failing: static guess with loose priors
};
// "ground truth", "visual-inertial", "static", "static (at rest)", "static (timeout)", "none".
std::string toString(StartKind kind);

// Gravity direction (roll, pitch) from the mean accelerometer over the window ending at t,
// yaw 0, zero velocity, zero biases. Valid for a static or hovering start.
// Throws InputError if the window has no IMU samples.
NavState staticInitialization(const std::vector<ImuSample>& imu, Timestamp t, double window_s);

// True when the mean accelerometer over the window ending at t has the norm of gravity and the
// gyro is steady (spread < 0.1 rad/s) with a mean a bias could explain (< 0.2 rad/s): the
// vehicle is at rest (or hovering very steadily).
bool imuIsStill(const std::vector<ImuSample>& imu, Timestamp t, double window_s);

// The true state at a time (run.init_from_groundtruth); e.g. groundTruthState on a sequence.
using GroundTruthFn = std::function<NavState(Timestamp)>;

class VioStarter {
 public:
  // imu: the IMU received so far (the caller appends to it; it must outlive the starter).
  // ground_truth: required when run.init_from_groundtruth. Throws InputError when it is missing.
  VioStarter(const CameraCalibration& camera, const std::vector<ImuSample>& imu,
             const VioRunOptions& run, const ImuNoiseParams& imu_params,
             GroundTruthFn ground_truth = nullptr);

  // frame: the observations of one image (landmark id, distorted pixel), in time order; the
  // IMU received must cover frame.t. Returns the first state (at frame.t) once the start is
  // decided, then nullopt for every later frame.
  std::optional<NavState> addFrame(const FrameObservations& frame);

  // True while frames without observations would do: the VI initialization is not used.
  bool needsObservations() const { return vi_init_.has_value() && !decided_; }
  bool started() const { return decided_; }
  StartKind kind() const { return kind_; }
  // The VI initialization's last attempt (its success or its last failure); null without one.
  const ViInitResult* viInitResult() const;
  int viInitAttempts() const { return vi_init_ ? vi_init_->attempts() : 0; }
  // Why no start was decided (for the error when a sequence ends first).
  std::string notStartedReason() const;

 private:
  const std::vector<ImuSample>& imu_;
  VioRunOptions run_;
  GroundTruthFn ground_truth_;
  std::optional<ViInitializer> vi_init_;
  std::optional<Timestamp> first_frame_t_;
  bool decided_ = false;
  StartKind kind_ = StartKind::kNone;
};

}  // namespace hdvio
