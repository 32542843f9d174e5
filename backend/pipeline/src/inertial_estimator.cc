#include "hdvio/pipeline/inertial_estimator.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace hdvio {

InertialEstimator::InertialEstimator(const InertialEstimatorOptions& options,
                                     const DisplacementSourceFactory& source)
    : options_(options),
      imu_(std::make_shared<std::vector<ImuSample>>()),
      thrust_(std::make_shared<std::vector<ThrustSample>>()) {
  if (options.displacement != DisplacementUse::kNone) {
    imo::checkRunOptions(options.run);
    if (!source) throw std::invalid_argument("IMO run: the displacements need a source");
    source_ = source(InertialBuffers{imu_, thrust_});
  }
  if (options.gate && !(options.gate->options.pixel_sigma > 0.0))
    throw std::invalid_argument("gate_io: pixel sigma must be positive");
}

void InertialEstimator::addImu(const ImuSample& s) {
  if (!imu_->empty() && s.t <= imu_->back().t) return;
  imu_->push_back(s);
  pump();
}

void InertialEstimator::addThrust(const ThrustSample& s) {
  if (!thrust_->empty() && s.t <= thrust_->back().t) return;
  thrust_->push_back(s);
  pump();
}

void InertialEstimator::addFrame(const imo::GateFrame& frame) {
  if (!options_.gate || (last_frame_t_ && frame.t < *last_frame_t_)) return;
  last_frame_t_ = frame.t;
  frames_.push_back(frame);
  pump();
}

void InertialEstimator::initialize(const NavState& init) {
  const auto it = std::lower_bound(imu_->begin(), imu_->end(), init.t,
                                   [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (it == imu_->end() || it->t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  // Gate frames first: at a frame on the grid the clone carries the gate update.
  std::vector<std::unique_ptr<imo::ImoUpdater>> updaters;
  if (options_.gate) {
    auto gate = std::make_unique<imo::GateCornerUpdater>(options_.gate->options, options_.gate->camera,
                                                         options_.gate->T_BC);
    gate_ = gate.get();
    updaters.push_back(std::move(gate));
  }
  imo::ImoFilterOptions filter = options_.run.filter;
  switch (options_.displacement) {
    case DisplacementUse::kFilterUpdate:
      updaters.push_back(std::make_unique<imo::DisplacementUpdater>(options_.run, source_));
      break;
    case DisplacementUse::kConcatenate:
      // net_only dead-reckons with the two samples' mean and the mid-step attitude.
      filter.release_propagation = false;
      filter.rotation_error = imo::RotationError::kRight;
      updaters.push_back(std::make_unique<imo::DisplacementConcatenation>(options_.run, source_));
      break;
    case DisplacementUse::kNone:
      break;
  }
  const bool imu_rate_states = options_.displacement != DisplacementUse::kConcatenate;
  stepper_ = std::make_unique<imo::ImoStepper>(filter, init, *it, std::move(updaters), imu_rate_states);
  next_ = static_cast<std::size_t>(it - imu_->begin()) + 1;
  pump();
}

void InertialEstimator::finish() {
  finished_ = true;
  pump();
}

// Sample k may go to the filter when no frame can still fall into its interval (gate updates:
// something later has arrived) and, at an update time of a thrust-driven source, the thrust
// reached it.
bool InertialEstimator::ready(std::size_t k) const {
  const Timestamp t = (*imu_)[k].t;
  if (stop_after_ && t > *stop_after_) return false;
  if (finished_) return true;
  if (options_.gate && !(k + 1 < imu_->size() || (last_frame_t_ && *last_frame_t_ > t))) return false;
  if (!options_.source_needs_thrust || stepper_->nextWindowEnd() > t) return true;
  return !thrust_->empty() && thrust_->back().t >= t;
}

void InertialEstimator::pump() {
  if (!stepper_) return;
  while (next_ < imu_->size() && ready(next_)) {
    const ImuSample& b = (*imu_)[next_];
    for (; !frames_.empty() && frames_.front().t <= b.t; frames_.pop_front()) gate_->addFrame(frames_.front());
    stepper_->addImu(b);
    ++next_;
  }
}

NavState InertialEstimator::state() const {
  if (!stepper_) throw std::logic_error("InertialEstimator: no state before initialize()");
  return stepper_->state();
}

const imo::ImoRunOutput& InertialEstimator::output() const {
  if (!stepper_) throw std::logic_error("InertialEstimator: no output before initialize()");
  return stepper_->output();
}

imo::ImoRunOutput& InertialEstimator::output() {
  if (!stepper_) throw std::logic_error("InertialEstimator: no output before initialize()");
  return stepper_->output();
}

}  // namespace hdvio
