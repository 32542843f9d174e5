#pragma once
// gate_io: the IMO error-state EKF driven by the IMU and corrected at every camera frame by the
// reprojections of known race-gate corners (docs/gate_io.md). Optionally the displacement
// measurements of a DisplacementSource (a learned network) are fused as in runImoFilter: clones
// on the update grid, one relative-position update per window.
#include <functional>
#include <memory>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/gate_reprojection.h"
#include "hdvio/backend/imo/imo_runner.h"
#include "hdvio/core/nav_state.h"

namespace hdvio::imo {

// The corners detected in one camera frame.
struct GateFrame {
  Timestamp t = 0;
  std::vector<GateCornerObservation> corners;
};

struct GateIoOptions {
  ImoRunOptions imo;               // filter noise and initial covariance; grid/window for displacements
  double pixel_sigma = 1.5;        // px, corner detection noise
  double gate_probability = 0.999;  // chi-square gate per frame (2 k dof); <= 0 disables
  // Chi-square gate per corner (2 dof, each corner against its own 2x2 innovation covariance)
  // before the frame update: drops single bad corners and keeps the rest. <= 0 disables.
  double corner_gate_probability = -1.0;
  bool fuse_displacements = false;  // needs a source
};

struct GateIoOutput {
  std::vector<NavState> states;  // the initial state and one per IMU sample after it
  double propagation_s = 0.0;    // thread CPU time per stage
  double gate_update_s = 0.0;
  double source_s = 0.0;
  double displacement_update_s = 0.0;
  int frames_applied = 0;
  int frames_rejected = 0;  // by the chi-square gate
  long corners_rejected = 0;  // by the per-corner gate
  long corners_used = 0;
  double mean_chi2_per_dof = 0.0;  // r' S^-1 r / (2 k) over all frames: ~1 for a consistent filter
  int displacement_updates = 0;
  int displacement_rejected = 0;
  int no_displacement = 0;
};

// Throws std::invalid_argument for unusable options (pixel sigma, displacement fusion without a
// source or with an inconsistent grid).
void checkGateIoOptions(const GateIoOptions& options, const DisplacementSource& source);

// gate_io one IMU sample at a time, as runGateIo below does over a whole stream (the streaming
// GateEstimator, backend/pipeline/gate_estimator.h, feeds it): each IMU interval is split at
// the frame times and, when fusing, the update-grid times inside it. It keeps the output.
class GateIoStepper {
 public:
  // first: the IMU sample at init.t. Throws as checkGateIoOptions.
  GateIoStepper(const GateIoOptions& options, const CameraModel& camera, const Pose& T_BC,
                const NavState& init, const ImuSample& first, DisplacementSource source);
  ~GateIoStepper();
  GateIoStepper(const GateIoStepper&) = delete;
  GateIoStepper& operator=(const GateIoStepper&) = delete;

  // A frame to apply in the IMU interval that holds its time: give it before the sample that
  // ends that interval. Ignored if not after the last sample stepped (init.t at the start) or
  // before the previous frame.
  void addFrame(const GateFrame& frame);
  // The next sample, strictly after the previous one.
  void addImu(const ImuSample& sample);
  // The next displacement-grid time (fusing), else the largest Timestamp.
  Timestamp nextGridTime() const;
  NavState state() const;
  const GateIoOutput& output() const;
  GateIoOutput& output();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The filter starts at init.t (an IMU sample time) from init's pose, velocity and biases.
// frames must be time-ordered; frames outside (init.t, last IMU time] are ignored.
// camera: the cam0 model; T_BC: camera -> body. source may be empty unless fuse_displacements.
GateIoOutput runGateIo(const std::vector<ImuSample>& imu, const NavState& init,
                       const GateIoOptions& options, const CameraModel& camera, const Pose& T_BC,
                       const std::vector<GateFrame>& frames, const DisplacementSource& source,
                       const std::function<void(Timestamp)>& on_progress = {});

}  // namespace hdvio::imo
