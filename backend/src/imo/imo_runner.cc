#include "hdvio/backend/imo/imo_runner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <stdexcept>
#include <utility>

#include "hdvio/backend/imo/imo_run_support.h"

namespace hdvio::imo {
namespace {

// Stage times are this thread's CPU time (the cost on one core, independent of machine load),
// read around whole runs and around each update: propagation = total - time at the grid points.
struct Clock {
  using time_point = double;
  static double now() { return threadCpuSeconds(); }
};
double secondsSince(double t0) { return Clock::now() - t0; }

std::size_t startIndex(const std::vector<ImuSample>& imu, Timestamp t0) {
  auto it = std::lower_bound(imu.begin(), imu.end(), t0,
                             [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (it == imu.end() || it->t != t0)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  return static_cast<std::size_t>(it - imu.begin());
}

}  // namespace

void checkRunOptions(const ImoRunOptions& o) {
  if (!(o.update_rate_hz > 0.0) || !(o.window_s > 0.0))
    throw std::invalid_argument("IMO run: update rate and window must be positive");
  const double n = o.window_s * o.update_rate_hz;
  if (std::abs(n - std::round(n)) > 1e-9 || std::round(n) < 1)
    throw std::invalid_argument("IMO run: the window must be a whole number of update periods");
  if (fromSeconds(1.0 / o.update_rate_hz) * std::llround(n) != fromSeconds(o.window_s))
    throw std::invalid_argument("IMO run: the update period must be a whole number of ns");
}

struct ImoStepper::Impl {
  Mode mode;
  ImoRunOptions options;
  DisplacementSource source;
  Timestamp period, window;
  std::size_t window_clones;
  Mat3 fixed_cov;
  Timestamp init_t;
  ImuSample prev;      // the last sample walked
  Timestamp next_grid;
  ImoRunOutput out;
  double grid_s = 0.0;  // clone, source, update, marginalization
  // Filter: the EKF and the gyro integration since the start (filter bias at each step), the
  // relative rotation used to carry a clone's rotation across a network window.
  std::optional<ImoFilter> filter;
  Quat gamma = Quat::Identity();
  Vec3 init_bg = Vec3::Zero(), init_ba = Vec3::Zero();
  RotationHistory history;
  // Network only: dead reckoning (orientation, first window) and the grid positions.
  ImoNominalState x;
  std::deque<std::pair<Timestamp, Vec3>> grid_positions;
  Vec3 last_velocity = Vec3::Zero();

  void step(const ImuSample& from, const ImuSample& to);
  void atGrid(Timestamp t);
  void afterSample(Timestamp t);
};

ImoStepper::ImoStepper(Mode mode, const ImoRunOptions& options, const NavState& init,
                       const ImuSample& first, DisplacementSource source)
    : impl_(std::make_unique<Impl>()) {
  checkRunOptions(options);
  if (first.t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  Impl& m = *impl_;
  m.mode = mode;
  m.options = options;
  m.source = std::move(source);
  m.period = fromSeconds(1.0 / options.update_rate_hz);
  m.window = fromSeconds(options.window_s);
  m.window_clones = static_cast<std::size_t>(std::llround(options.window_s * options.update_rate_hz));
  m.fixed_cov = options.measurement_sigma.cwiseAbs2().asDiagonal();
  m.init_t = init.t;
  m.prev = first;
  m.next_grid = first.t + m.period;
  if (mode == Mode::kFilter) {
    m.filter.emplace(options.filter);
    m.filter->initialize(nominalFrom(init));
    m.init_bg = m.filter->state().bg;
    m.init_ba = m.filter->state().ba;
    m.history.add(init.t, m.gamma);
    m.filter->addClone();
    m.out.states.push_back(navFrom(m.filter->state()));
  } else {
    m.x = nominalFrom(init);
    m.history.add(m.x.t, Quat(m.x.R));
    m.grid_positions.emplace_back(m.x.t, m.x.p);
    m.last_velocity = m.x.v;
    m.out.states.push_back(navFrom(m.x));
  }
}

ImoStepper::~ImoStepper() = default;

void ImoStepper::Impl::step(const ImuSample& from, const ImuSample& to) {
  if (mode == Mode::kNetworkOnly) {
    x = propagateStep(x, 0.5 * (from.gyro + to.gyro), 0.5 * (from.accel + to.accel),
                      secondsBetween(from.t, to.t), options.filter.gravity)
            .state;
    x.t = to.t;
    history.add(to.t, Quat(x.R));
    return;
  }
  // Release propagation: the interval's newer sample held over it (zero-order hold).
  const bool hold = options.filter.release_propagation;
  const Vec3 gyro = hold ? to.gyro : Vec3(0.5 * (from.gyro + to.gyro));
  const Vec3 accel = hold ? to.accel : Vec3(0.5 * (from.accel + to.accel));
  const Vec3& bg = options.initial_window_biases ? init_bg : filter->state().bg;
  gamma = (gamma * quatExp((gyro - bg) * secondsBetween(from.t, to.t))).normalized();
  filter->propagate(gyro, accel, to.t);
  history.add(to.t, gamma);
}

void ImoStepper::Impl::atGrid(Timestamp t_end) {
  if (mode == Mode::kNetworkOnly) {
    Vec3 p = x.p;
    if (t_end - init_t >= window) {
      DisplacementRequest request;
      request.t_begin = t_end - window;
      request.t_end = t_end;
      request.world_from_body = [this](Timestamp tt) { return history.at(tt); };
      request.gyro_bias = x.bg;
      request.accel_bias = x.ba;
      const auto t0 = Clock::now();
      const std::optional<DisplacementEstimate> est = source(request);
      out.source_s += secondsSince(t0);
      if (est && (est->velocity_coefficient != 0.0 || !est->velocity_matrix.isZero(0.0) ||
                  !est->attitude_jacobian.isZero(0.0)))
        throw std::invalid_argument("network-only needs a pure displacement source");
      const Vec3 p_begin = grid_positions.front().second;  // at t - window
      if (est) {
        p = p_begin + est->z;
        last_velocity = est->z / options.window_s;
        ++out.updates;
      } else {
        p = grid_positions.back().second + last_velocity * secondsBetween(grid_positions.back().first, t_end);
        ++out.no_measurement;
      }
      grid_positions.pop_front();
    }
    grid_positions.emplace_back(t_end, p);
    NavState s = navFrom(x);
    s.t = t_end;
    s.T_WB = Pose(x.R, p);
    s.v_W = last_velocity;
    out.states.push_back(s);
    return;
  }
  // Three clock reads per grid point (each costs ~1.4 us of thread CPU time on the VM of
  // docs/benchmarks.md): the source runs first, before the clone at t_end is added, which it
  // does not read (clone i, the biases and the rotation history are unchanged by cloning).
  const double t_grid = Clock::now();
  const Timestamp t_begin = t_end - window;
  const int i = filter->findClone(t_begin);
  if (i < 0) {  // not one window of clones yet
    filter->addClone();
    while (filter->clones().size() > window_clones + 1) filter->marginalizeClone(0);
    grid_s += secondsSince(t_grid);
    return;
  }
  DisplacementRequest request = windowRequest(*filter, history, i, t_begin, t_end);
  if (options.initial_window_biases) {
    request.gyro_bias = init_bg;
    request.accel_bias = init_ba;
  }
  const std::optional<DisplacementEstimate> est = source(request);
  const double t_update = Clock::now();
  out.source_s += t_update - t_grid;
  filter->addClone();
  const int j = static_cast<int>(filter->clones().size()) - 1;
  if (!est) {
    ++out.no_measurement;
  } else {
    const RelativePositionMeasurement meas = displacementMeasurement(
        *est, i, j, options.use_source_covariance ? est->covariance : fixed_cov);
    const bool applied = filter->update(meas) == UpdateOutcome::kApplied;
    if (applied) ++out.updates;
    else ++out.rejected;
    out.innovations.push_back({t_end, filter->lastInnovation(), applied});
  }
  while (!filter->clones().empty() && filter->clones().front().t <= t_begin)
    filter->marginalizeClone(0);
  history.dropBefore(filter->clones().front().t);
  grid_s += secondsSince(t_grid);
}

void ImoStepper::Impl::afterSample(Timestamp t) {
  if (mode == Mode::kFilter) out.states.push_back(navFrom(filter->state()));
  else history.dropBefore(t - window - period);
}

// Splits the interval from the previous sample at the grid times; each piece is integrated
// with its two end samples (the grid ends interpolated between the two real samples).
void ImoStepper::addImu(const ImuSample& b) {
  Impl& m = *impl_;
  ImuSample cur = m.prev;
  while (m.next_grid <= b.t) {
    if (m.next_grid > cur.t) {
      const ImuSample mid = interpolateImu(m.prev, b, m.next_grid);
      m.step(cur, mid);
      cur = mid;
    }
    m.atGrid(m.next_grid);
    m.next_grid += m.period;
  }
  if (b.t > cur.t) m.step(cur, b);
  m.prev = b;
  m.afterSample(b.t);
}

Timestamp ImoStepper::nextGridTime() const { return impl_->next_grid; }
NavState ImoStepper::state() const {
  return impl_->mode == Mode::kFilter ? navFrom(impl_->filter->state()) : impl_->out.states.back();
}
const ImoRunOutput& ImoStepper::output() const { return impl_->out; }
ImoRunOutput& ImoStepper::output() { return impl_->out; }
double ImoStepper::gridSeconds() const { return impl_->grid_s; }

namespace {
ImoRunOutput runStepper(ImoStepper::Mode mode, const std::vector<ImuSample>& imu,
                        const NavState& init, const ImoRunOptions& options,
                        const DisplacementSource& source,
                        const std::function<void(Timestamp)>& on_progress) {
  checkRunOptions(options);
  const std::size_t k0 = startIndex(imu, init.t);
  ImoStepper stepper(mode, options, init, imu[k0], source);
  // growing the states costs reallocation and page faults per step
  if (mode == ImoStepper::Mode::kFilter) stepper.output().states.reserve(imu.size() - k0);
  const double t_run = Clock::now();
  for (std::size_t k = k0 + 1; k < imu.size(); ++k) {
    stepper.addImu(imu[k]);
    if (on_progress) on_progress(imu[k].t);
  }
  ImoRunOutput out = std::move(stepper.output());
  if (mode == ImoStepper::Mode::kFilter) {
    out.propagation_s = secondsSince(t_run) - stepper.gridSeconds();  // with the per-sample state output
    out.update_s = stepper.gridSeconds() - out.source_s;
  } else {
    out.propagation_s = secondsSince(t_run) - out.source_s;  // with concatenation and output
  }
  return out;
}
}  // namespace

ImoRunOutput runImoFilter(const std::vector<ImuSample>& imu, const NavState& init,
                          const ImoRunOptions& options, const DisplacementSource& source,
                          const std::function<void(Timestamp)>& on_progress) {
  return runStepper(ImoStepper::Mode::kFilter, imu, init, options, source, on_progress);
}

ImoRunOutput runNetworkOnly(const std::vector<ImuSample>& imu, const NavState& init,
                            const ImoRunOptions& options, const DisplacementSource& source,
                            const std::function<void(Timestamp)>& on_progress) {
  return runStepper(ImoStepper::Mode::kNetworkOnly, imu, init, options, source, on_progress);
}

}  // namespace hdvio::imo
