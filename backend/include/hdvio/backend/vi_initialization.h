#pragma once
// Visual-inertial initialization from a short window of frames (VINS-Mono / ORB-SLAM3 style):
// visual SfM up to scale, gyro bias from visual vs preintegrated rotations, linear alignment
// for velocities, gravity and metric scale, gravity refinement on |g| = 9.81. Works from a
// moving start; reports failure with a reason (too little parallax or excitation, too few
// tracks) instead of returning garbage, so the caller can retry with a later / longer window.
//
// Output gauge: gravity-aligned world (z up), the first frame's body at the origin with yaw 0.
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "hdvio/core/nav_state.h"
#include "hdvio/backend/vi_init_alignment.h"
#include "hdvio/backend/vi_init_sfm.h"
#include "hdvio/backend/vio_backend.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/factors/imu_preintegration.h"

namespace hdvio {

struct ViInitOptions {
  int min_frames = 5;
  vi_init::SfmOptions sfm;
  vi_init::AlignmentOptions alignment;
  int gyro_bias_iterations = 2;
  double max_gyro_bias = 0.5;              // rad/s; larger means the rotations disagree
  double max_reprojection_rms_px = 2.0;    // after bundle adjustment
  double max_gravity_norm_error = 1.0;     // m/s^2, free-gravity linear estimate vs 9.81
  double max_scale_relative_std = 0.03;    // too little acceleration makes scale unobservable
  double max_alignment_rms = 0.1;          // m, m/s: the equations must be consistent
};

// Why an attempt failed, for the caller's policy (e.g. fall back to a static initialization
// when the camera has no parallax and the IMU says the vehicle is still).
enum class ViInitFailure {
  kNone,
  kNotEnoughData,            // too few frames, IMU gaps
  kInsufficientParallax,     // static or purely rotating camera: wait for translation
  kVisual,                   // too few tracks / inliers / landmarks, bad reprojection
  kInsufficientExcitation,   // scale or gravity not observable: wait for acceleration changes
  kInconsistent,             // visual and inertial motion disagree (calibration, time offset)
};

struct ViInitResult {
  bool success = false;
  ViInitFailure failure = ViInitFailure::kNone;
  std::string reason;              // why it failed, for people (empty on success)
  std::vector<NavState> states;    // one per input frame, in the output gauge
  std::map<int, Vec3> landmarks_W; // triangulated landmarks, metric, output gauge
  // Diagnostics (filled as far as the pipeline got).
  int reference_frame = -1;
  double parallax_deg = 0.0;       // median rotation-compensated parallax first/reference frame
  double reprojection_rms_px = 0.0;
  double scale = 0.0;              // metres per SfM unit
  double scale_relative_std = 0.0;
  double gravity_norm_linear = 0.0;  // |g| of the free-gravity linear solution
  double alignment_rms = 0.0;

  const NavState& latest() const { return states.back(); }
};

// frames: time-ordered observations (distorted pixels); imu must cover [front.t, back.t].
// T_BC: camera -> body. Biases start at zero; the returned biases are [bg, ba] with ba from
// the alignment when options.alignment.estimate_accel_bias, else zero.
ViInitResult initializeVisualInertial(const std::vector<FrameObservations>& frames,
                                      const std::vector<ImuSample>& imu,
                                      const CameraModel& camera, const Pose& T_BC,
                                      const ImuNoiseParams& imu_params,
                                      const ViInitOptions& options = {});

// Streaming use: keeps the frames of the last window_s seconds and, once they span it, tries
// to initialize on max_frames of them (evenly strided, ending at the newest) every retry_every
// frames. Constant-acceleration stretches leave scale unobservable, so ~2 s windows work far
// better than ~1 s ones (docs/vi_initialization.md).
class ViInitializer {
 public:
  ViInitializer(const CameraModel& camera, const Pose& T_BC, const ImuNoiseParams& imu_params,
                const ViInitOptions& options = {}, double window_s = 2.0, int max_frames = 20,
                int retry_every = 2);

  // imu must cover the frames given so far. Returns true when this frame completed a
  // successful initialization (result().latest() is then the state at frame.t).
  bool addFrame(const FrameObservations& frame, const std::vector<ImuSample>& imu);
  const ViInitResult& result() const { return result_; }
  int attempts() const { return attempts_; }

 private:
  CameraModel camera_;
  Pose T_BC_;
  ImuNoiseParams imu_params_;
  ViInitOptions options_;
  double window_s_;
  int max_frames_, retry_every_;
  std::deque<FrameObservations> window_;
  int since_attempt_ = 0;
  int attempts_ = 0;
  ViInitResult result_;
};

}  // namespace hdvio
