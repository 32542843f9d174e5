#pragma once
// Runs a visual-inertial backend over a whole sequence, feeding sensor data in time order.
// Without a frontend, the frames are the simulator's ground-truth landmark tracks, optionally
// with added pixel noise.
#include <cstdint>
#include <string>
#include <vector>

#include "hdvio/backend/vi_initialization.h"
#include "hdvio/backend/vio_backend.h"
#include "hdvio/core/sequence.h"

namespace hdvio {

struct VioRunOptions {
  bool init_from_groundtruth = false;  // else: visual-inertial initialization (below)
  // All of the start logic lives in VioStarter (vio_starter.h), shared with the image runner.
  // Visual-inertial initialization (vi_initialization.h) over this window; while the camera
  // sees no parallax and the IMU says the vehicle is still, the static initialization is used
  // instead. false: static (hover) initialization only, as for a start at rest.
  bool visual_inertial_init = true;
  double vi_init_window_s = 2.0;
  double vi_init_timeout_s = 5.0;  // then the static guess, whatever the motion
  double static_init_window_s = 0.5;
  double guess_velocity_sigma = 1.0;  // prior sigmas of the guessed first state (m/s, rad)
  double guess_tilt_sigma = 0.1;
  double pixel_noise_sigma = 0.0;      // added to simulated tracks
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

struct VioRunOutput {
  std::vector<NavState> states;       // one per processed frame, latest estimate at that time
  std::vector<FrameResult> frames;
  double backend_time_s = 0.0;        // wall time spent in the backend
  bool visual_inertial_start = false;  // the first state came from the VI initialization
  StartKind start = StartKind::kNone;
  Timestamp start_t = 0;               // time of the first state
  int vi_init_attempts = 0;
  ViInitResult vi_init;                // the VI initialization's last attempt (if any)
};

// Gravity direction (roll, pitch) from the mean accelerometer, yaw 0, zero velocity, gyro bias
// from the mean gyro over the window ending at t. Valid for a static or hovering start.
// Throws InputError if the window has no IMU samples.
NavState staticInitialization(const std::vector<ImuSample>& imu, Timestamp t, double window_s);

// True when the mean accelerometer over the window ending at t has the norm of gravity and the
// gyro is steady (spread < 0.1 rad/s) with a mean a bias could explain (< 0.2 rad/s): the
// vehicle is at rest (or hovering very steadily).
bool imuIsStill(const std::vector<ImuSample>& imu, Timestamp t, double window_s);

// Ground-truth state at t (linear / slerp interpolation); throws InputError when t is outside.
NavState groundTruthState(const Sequence& seq, Timestamp t);

// Frames of landmark observations grouped by timestamp (simulated sequences).
std::vector<FrameObservations> framesFromTracks(const Sequence& seq, double pixel_noise_sigma,
                                                std::uint32_t seed);

VioRunOutput runVioOnTracks(const Sequence& seq, const VioBackendOptions& options,
                            const VioRunOptions& run,
                            ResidualForceSource residual_force = nullptr);

}  // namespace hdvio
