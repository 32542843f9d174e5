#pragma once
// The streaming object of gate_io (docs/gate_io.md): the IMO error-state EKF propagated with the
// IMU and corrected by the reprojections of known race-gate corners, optionally fusing a
// displacement source's windows. A program feeds IMU, thrust (for a thrust-driven source) and
// gate frames in time order and asks for the state; inside, imo::GateIoStepper.
//
// Feeding order: a frame before the first IMU sample after its time (at equal times IMU first,
// as a camera frame needs the IMU up to its time). An IMU sample therefore reaches the filter
// once something later has arrived (an IMU sample or a frame), or at finish(): its interval
// may still receive a frame until then. When fusing with a thrust-driven source, a sample whose
// interval holds an update time also waits for the thrust up to its time. The estimate is then
// the one of the whole recording fed at once (imo::runGateIo).
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "hdvio/backend/imo/gate_io_runner.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/pipeline/inertial_estimator.h"

namespace hdvio {

struct GateEstimatorOptions {
  imo::GateIoOptions gate;
  bool source_needs_thrust = false;  // windows wait for the thrust up to their end
};

class GateEstimator {
 public:
  // source: the displacement source over the estimator's buffers (may be empty unless
  // gate.fuse_displacements). T_BC: camera -> body.
  GateEstimator(const GateEstimatorOptions& options, const CameraModel& camera, const Pose& T_BC,
                const DisplacementSourceFactory& source = {});

  // Samples not after the previous one are ignored; frames before the previous one too.
  void addImu(const ImuSample& sample);
  void addThrust(const ThrustSample& sample);
  void addFrame(const imo::GateFrame& frame);
  // Starts the filter at init.t, the time of an IMU sample already received (its pose,
  // velocity and biases [bg, ba]); frames at or before it are not used. Throws
  // std::invalid_argument otherwise or for unusable options.
  void initialize(const NavState& init);
  // Samples after t do not reach the filter (a limited run).
  void stopAfter(Timestamp t) { stop_after_ = t; }
  // No more measurements: the samples still waiting go to the filter.
  void finish();

  bool initialized() const { return stepper_ != nullptr; }
  // The latest estimate; throws std::logic_error before initialize().
  NavState state() const;
  // The initial state and one per IMU sample that reached the filter, and the counters.
  const imo::GateIoOutput& output() const;
  imo::GateIoOutput& output();

 private:
  bool ready(std::size_t k) const;
  void pump();

  GateEstimatorOptions options_;
  CameraModel camera_;
  Pose T_BC_;
  std::shared_ptr<std::vector<ImuSample>> imu_;
  std::shared_ptr<std::vector<ThrustSample>> thrust_;
  imo::DisplacementSource source_;
  std::deque<imo::GateFrame> frames_;  // received, not yet given to the stepper
  std::optional<Timestamp> last_frame_t_;
  std::unique_ptr<imo::GateIoStepper> stepper_;
  std::size_t next_ = 0;  // the next IMU sample for the filter
  std::optional<Timestamp> stop_after_;
  bool finished_ = false;
};

// Detections grouped per frame (time order), each corner with its known world position.
std::vector<imo::GateFrame> gateFrames(const io::GateData& data);

}  // namespace hdvio
