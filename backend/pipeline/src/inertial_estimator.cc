#include "hdvio/pipeline/inertial_estimator.h"

#include <algorithm>
#include <stdexcept>

namespace hdvio {

InertialEstimator::InertialEstimator(const InertialEstimatorOptions& options,
                                     const DisplacementSourceFactory& source)
    : options_(options),
      imu_(std::make_shared<std::vector<ImuSample>>()),
      thrust_(std::make_shared<std::vector<ThrustSample>>()) {
  imo::checkRunOptions(options.run);
  source_ = source ? source(InertialBuffers{imu_, thrust_}) : imo::DisplacementSource{};
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

void InertialEstimator::initialize(const NavState& init) {
  const auto it = std::lower_bound(imu_->begin(), imu_->end(), init.t,
                                   [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (it == imu_->end() || it->t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  const auto mode = options_.network_only ? imo::ImoStepper::Mode::kNetworkOnly
                                          : imo::ImoStepper::Mode::kFilter;
  stepper_ = std::make_unique<imo::ImoStepper>(mode, options_.run, init, *it, source_);
  next_ = static_cast<std::size_t>(it - imu_->begin()) + 1;
  pump();
}

void InertialEstimator::finish() {
  finished_ = true;
  pump();
}

// A sample may go to the filter when no update time falls into its interval, or the source
// has what the window ending there needs.
bool InertialEstimator::ready(Timestamp t) const {
  if (finished_ || !options_.source_needs_thrust || stepper_->nextGridTime() > t) return true;
  return !thrust_->empty() && thrust_->back().t >= t;
}

void InertialEstimator::pump() {
  if (!stepper_) return;
  while (next_ < imu_->size()) {
    const ImuSample& b = (*imu_)[next_];
    if ((stop_after_ && b.t > *stop_after_) || !ready(b.t)) return;
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

double InertialEstimator::gridSeconds() const { return stepper_ ? stepper_->gridSeconds() : 0.0; }

}  // namespace hdvio
