#pragma once
// One object for every inertial method (imo, tlio, model_ekf, net_only, gate_io): a program
// feeds it IMU, thrust and (gate_io) gate-corner frames in time order and asks for the state.
// Inside: the IMO EKF driver (imo::ImoStepper) with the updaters the options choose once
// (imo_updaters.h), and the displacement source (the learned network,
// displacement_network_source.h, or the drag model) reading the samples received so far.
//
// A window's displacement needs the measurements up to the window's end: an IMU sample whose
// interval holds an update time waits until the thrust (when the source uses it) has reached
// it. With gate updates a sample also waits until something later has arrived (an IMU sample
// or a frame), since until then a frame may still fall into its interval: the estimate lags
// the stream by one IMU sample. So the estimate is the one of the whole recording fed at once.
// finish() says no more measurements come and runs the samples still waiting. hdvio_run feeds
// whole sequences through inertial_sequence_runner.h. docs/imo.md, docs/gate_io.md.
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hdvio/backend/imo/imo_stepper.h"
#include "hdvio/backend/imo/imo_updaters.h"

namespace hdvio {

// What the displacement source's estimates do.
enum class DisplacementUse {
  kFilterUpdate,  // relative-position updates on the clone grid (imo, tlio, model_ekf)
  kConcatenate,   // net_only: concatenated, no filter update
  kNone,          // no source (gate_io without a network)
};

// The known race-gate corners' reprojections at camera frames (gate_io).
struct GateCornerUpdates {
  imo::GateCornerOptions options;
  CameraModel camera;  // cam0
  Pose T_BC;           // camera -> body
};

struct InertialEstimatorOptions {
  imo::ImoRunOptions run;  // the filter; grid, window and measurement noise of the displacements
  DisplacementUse displacement = DisplacementUse::kFilterUpdate;
  std::optional<GateCornerUpdates> gate;
  bool source_needs_thrust = false;  // windows wait for the thrust up to their end
};

// What the displacement source reads: the estimator's growing buffers.
struct InertialBuffers {
  std::shared_ptr<const std::vector<ImuSample>> imu;
  std::shared_ptr<const std::vector<ThrustSample>> thrust;
};
using DisplacementSourceFactory = std::function<imo::DisplacementSource(const InertialBuffers&)>;

class InertialEstimator {
 public:
  // source may be empty only with DisplacementUse::kNone. Throws std::invalid_argument for
  // unusable options.
  InertialEstimator(const InertialEstimatorOptions& options, const DisplacementSourceFactory& source);

  // Samples not after the previous one are ignored; frames before the previous one too, and
  // all frames without gate updates.
  void addImu(const ImuSample& sample);
  void addThrust(const ThrustSample& sample);
  void addFrame(const imo::GateFrame& frame);
  // Starts the filter at init.t, the time of an IMU sample already received (its pose,
  // velocity and biases [bg, ba]); frames at or before it are not used. Throws
  // std::invalid_argument otherwise.
  void initialize(const NavState& init);
  // Samples after t reach the source's windows only, not the filter (a limited run).
  void stopAfter(Timestamp t) { stop_after_ = t; }
  void finish();

  bool initialized() const { return stepper_ != nullptr; }
  // The latest estimate; throws std::logic_error before initialize().
  NavState state() const;
  // Every state so far (the initial one, then one per IMU sample, or per update time for
  // net_only) and the counters; the updaters' stage times are filled, the propagation time is
  // the caller's.
  const imo::ImoRunOutput& output() const;
  imo::ImoRunOutput& output();

 private:
  bool ready(std::size_t k) const;
  void pump();

  InertialEstimatorOptions options_;
  std::shared_ptr<std::vector<ImuSample>> imu_;
  std::shared_ptr<std::vector<ThrustSample>> thrust_;
  imo::DisplacementSource source_;
  std::deque<imo::GateFrame> frames_;  // received, not yet given to the gate updater
  std::optional<Timestamp> last_frame_t_;
  std::unique_ptr<imo::ImoStepper> stepper_;
  imo::GateCornerUpdater* gate_ = nullptr;  // owned by stepper_
  std::size_t next_ = 0;  // the next IMU sample for the filter
  std::optional<Timestamp> stop_after_;
  bool finished_ = false;
};

}  // namespace hdvio
