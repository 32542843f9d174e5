#pragma once
// How a visual-inertial run gets its first state, shared by the track runner (vio_runner) and
// the image runner (apps/run visual_image_runner): ground truth when asked for, else the
// visual-inertial initialization over a window of frames (moving start), the static
// initialization when the camera sees no parallax and the IMU is still (start at rest), and the
// static guess after a timeout whatever the motion. Feed every frame until start() returns a
// state; the caller then initializes its backend (and frontend) with it.
#include <optional>
#include <string>
#include <vector>

#include "hdvio/backend/nav_state.h"
#include "hdvio/backend/vi_initialization.h"
#include "hdvio/backend/vio_runner.h"
#include "hdvio/core/sequence.h"

namespace hdvio {

class VioStarter {
 public:
  // seq provides the IMU (and ground truth for run.init_from_groundtruth); it must outlive
  // the starter. Throws InputError when the sequence has no camera calibration or no IMU.
  VioStarter(const Sequence& seq, const VioRunOptions& run, const ImuNoiseParams& imu_params);

  // frame: the observations of one image (landmark id, distorted pixel), in time order; the
  // IMU of the sequence must cover frame.t. Returns the first state (at frame.t) once the start
  // is decided, then nullopt for every later frame.
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
  const Sequence& seq_;
  VioRunOptions run_;
  std::optional<ViInitializer> vi_init_;
  std::optional<Timestamp> first_frame_t_;
  bool decided_ = false;
  StartKind kind_ = StartKind::kNone;
};

}  // namespace hdvio
