#include "hdvio/pipeline/gate_estimator.h"

#include <algorithm>
#include <stdexcept>

namespace hdvio {

GateEstimator::GateEstimator(const GateEstimatorOptions& options, const CameraModel& camera,
                             const Pose& T_BC, const DisplacementSourceFactory& source)
    : options_(options),
      camera_(camera),
      T_BC_(T_BC),
      imu_(std::make_shared<std::vector<ImuSample>>()),
      thrust_(std::make_shared<std::vector<ThrustSample>>()) {
  source_ = source ? source(InertialBuffers{imu_, thrust_}) : imo::DisplacementSource{};
  imo::checkGateIoOptions(options.gate, source_);
}

void GateEstimator::addImu(const ImuSample& s) {
  if (!imu_->empty() && s.t <= imu_->back().t) return;
  imu_->push_back(s);
  pump();
}

void GateEstimator::addThrust(const ThrustSample& s) {
  if (!thrust_->empty() && s.t <= thrust_->back().t) return;
  thrust_->push_back(s);
  pump();
}

void GateEstimator::addFrame(const imo::GateFrame& frame) {
  if (last_frame_t_ && frame.t < *last_frame_t_) return;
  last_frame_t_ = frame.t;
  frames_.push_back(frame);
  pump();
}

void GateEstimator::initialize(const NavState& init) {
  const auto it = std::lower_bound(imu_->begin(), imu_->end(), init.t,
                                   [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (it == imu_->end() || it->t != init.t)
    throw std::invalid_argument("gate_io: the initial time is not an IMU sample time");
  stepper_ = std::make_unique<imo::GateIoStepper>(options_.gate, camera_, T_BC_, init, *it, source_);
  next_ = static_cast<std::size_t>(it - imu_->begin()) + 1;
  pump();
}

void GateEstimator::finish() {
  finished_ = true;
  pump();
}

// Sample k may go to the filter when no frame can still fall into its interval (something
// later has arrived) and, at an update time of a thrust-driven source, the thrust reached it.
bool GateEstimator::ready(std::size_t k) const {
  const Timestamp t = (*imu_)[k].t;
  if (stop_after_ && t > *stop_after_) return false;
  if (finished_) return true;
  const bool frames_known = k + 1 < imu_->size() || (last_frame_t_ && *last_frame_t_ > t);
  if (!frames_known) return false;
  if (!options_.gate.fuse_displacements || !options_.source_needs_thrust || stepper_->nextGridTime() > t)
    return true;
  return !thrust_->empty() && thrust_->back().t >= t;
}

void GateEstimator::pump() {
  if (!stepper_) return;
  while (next_ < imu_->size() && ready(next_)) {
    const ImuSample& b = (*imu_)[next_];
    while (!frames_.empty() && frames_.front().t <= b.t) {
      stepper_->addFrame(frames_.front());
      frames_.pop_front();
    }
    stepper_->addImu(b);
    ++next_;
  }
}

NavState GateEstimator::state() const {
  if (!stepper_) throw std::logic_error("GateEstimator: no state before initialize()");
  return stepper_->state();
}

const imo::GateIoOutput& GateEstimator::output() const {
  if (!stepper_) throw std::logic_error("GateEstimator: no output before initialize()");
  return stepper_->output();
}

imo::GateIoOutput& GateEstimator::output() {
  if (!stepper_) throw std::logic_error("GateEstimator: no output before initialize()");
  return stepper_->output();
}

std::vector<imo::GateFrame> gateFrames(const io::GateData& data) {
  std::vector<imo::GateFrame> frames;
  for (const io::GateCornerDetection& d : data.detections) {
    if (frames.empty() || frames.back().t != d.t) frames.push_back({d.t, {}});
    frames.back().corners.push_back({data.corners.at({d.gate_id, d.corner_id}), Vec2(d.u, d.v)});
  }
  return frames;
}

}  // namespace hdvio
