#include "hdvio/backend/imo/imo_stepper.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "hdvio/backend/imo/imo_run_support.h"

namespace hdvio::imo {

void checkRunOptions(const ImoRunOptions& o) {
  if (!(o.update_rate_hz > 0.0) || !(o.window_s > 0.0))
    throw std::invalid_argument("IMO run: update rate and window must be positive");
  const double n = o.window_s * o.update_rate_hz;
  if (std::abs(n - std::round(n)) > 1e-9 || std::round(n) < 1)
    throw std::invalid_argument("IMO run: the window must be a whole number of update periods");
  if (fromSeconds(1.0 / o.update_rate_hz) * std::llround(n) != fromSeconds(o.window_s))
    throw std::invalid_argument("IMO run: the update period must be a whole number of ns");
}

ImoStepper::ImoStepper(const ImoFilterOptions& filter, const NavState& init, const ImuSample& first,
                       std::vector<std::unique_ptr<ImoUpdater>> updaters, bool imu_rate_states)
    : filter_(filter),
      updaters_(std::move(updaters)),
      hold_(filter.release_propagation),
      imu_rate_states_(imu_rate_states),
      prev_(first) {
  if (first.t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  filter_.initialize(nominalFrom(init));
  out_.states.push_back(navFrom(filter_.state()));
  for (const auto& u : updaters_) u->start(filter_, out_);
}

ImoStepper::~ImoStepper() = default;

void ImoStepper::step(const ImuSample& from, const ImuSample& to) {
  const Vec3 gyro = hold_ ? to.gyro : Vec3(0.5 * (from.gyro + to.gyro));
  const Vec3 accel = hold_ ? to.accel : Vec3(0.5 * (from.accel + to.accel));
  filter_.propagate(gyro, accel, to.t);
  for (const auto& u : updaters_) u->propagated(filter_, gyro, from.t, to.t);
}

// Splits the interval from the previous sample at the updaters' times; each piece is integrated
// with its two end samples (the split ends interpolated between the two real samples). At
// equal times the updaters act in their order (a gate frame before a grid time: the clone
// carries the gate update).
void ImoStepper::addImu(const ImuSample& b) {
  if (b.t <= prev_.t) throw std::invalid_argument("IMO run: IMU samples must be strictly increasing");
  ImuSample cur = prev_;
  while (true) {
    ImoUpdater* next = nullptr;
    Timestamp t_next = kNoUpdate;
    for (const auto& u : updaters_) {
      const Timestamp t = u->nextTime();
      if (t < t_next) t_next = t, next = u.get();
    }
    if (next == nullptr || t_next > b.t) break;
    if (t_next > cur.t) {
      const ImuSample mid = interpolateImu(prev_, b, t_next);
      step(cur, mid);
      cur = mid;
    }
    next->update(filter_, out_);
  }
  if (b.t > cur.t) step(cur, b);
  prev_ = b;
  if (imu_rate_states_) out_.states.push_back(navFrom(filter_.state()));
}

Timestamp ImoStepper::nextWindowEnd() const {
  Timestamp t = kNoUpdate;
  for (const auto& u : updaters_) t = std::min(t, u->nextWindowEnd());
  return t;
}

NavState ImoStepper::state() const {
  return imu_rate_states_ ? navFrom(filter_.state()) : out_.states.back();
}

}  // namespace hdvio::imo
