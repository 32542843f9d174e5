#pragma once
// One object for the inertial method family (imo, tlio, model_ekf: the IMO error-state EKF with
// a displacement source; net_only: the network's displacements concatenated): a program feeds
// it IMU and thrust in time order and asks for the state. Inside: the filter stepped one IMU
// sample at a time (imo::ImoStepper) and the displacement source (the learned network,
// displacement_network_source.h, or the drag model) reading the samples received so far.
//
// A window's displacement needs the measurements up to the window's end: an IMU sample whose
// interval holds an update time waits until the thrust (when the source uses it) has reached
// it, so the estimate is the one of the whole recording fed at once (imo::runImoFilter).
// finish() says no more samples come and runs the ones still waiting. hdvio_run feeds whole
// sequences through inertial_sequence_runner.h. docs/imo.md.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hdvio/backend/imo/imo_runner.h"

namespace hdvio {

struct InertialEstimatorOptions {
  imo::ImoRunOptions run;
  bool network_only = false;         // net_only: no filter
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
  InertialEstimator(const InertialEstimatorOptions& options, const DisplacementSourceFactory& source);

  // Samples not after the previous one are ignored.
  void addImu(const ImuSample& sample);
  void addThrust(const ThrustSample& sample);
  // Starts the filter at init.t, the time of an IMU sample already received (its pose,
  // velocity and biases [bg, ba]). Throws std::invalid_argument otherwise.
  void initialize(const NavState& init);
  // Samples after t reach the source's windows only, not the filter (a limited run).
  void stopAfter(Timestamp t) { stop_after_ = t; }
  void finish();

  bool initialized() const { return stepper_ != nullptr; }
  // The latest estimate; throws std::logic_error before initialize().
  NavState state() const;
  // Every state so far (the initial one, then one per IMU sample, or per update time for
  // net_only) and the update counters; source_s is filled, the propagation time is the caller's.
  const imo::ImoRunOutput& output() const;
  imo::ImoRunOutput& output();
  // Thread CPU time at the update times (clone, source, update, marginalization).
  double gridSeconds() const;

 private:
  bool ready(Timestamp t) const;
  void pump();

  InertialEstimatorOptions options_;
  std::shared_ptr<std::vector<ImuSample>> imu_;
  std::shared_ptr<std::vector<ThrustSample>> thrust_;
  imo::DisplacementSource source_;
  std::unique_ptr<imo::ImoStepper> stepper_;
  std::size_t next_ = 0;  // the next IMU sample for the filter
  std::optional<Timestamp> stop_after_;
  bool finished_ = false;
};

}  // namespace hdvio
