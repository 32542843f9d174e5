#include "hdvio/backend/imo/imo_runner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>

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

// Walks consecutive IMU samples, splitting each interval at the grid times (start + k period);
// `step(from, to)` integrates one piece with the two end samples, `at_grid(t)` runs after the
// piece that ends at a grid time, `after_sample(t)` after each IMU sample.
template <class Step, class AtGrid, class AfterSample>
void walkImu(const std::vector<ImuSample>& imu, std::size_t k0, Timestamp period, Step step,
             AtGrid at_grid, AfterSample after_sample) {
  Timestamp next_grid = imu[k0].t + period;
  for (std::size_t k = k0; k + 1 < imu.size(); ++k) {
    const ImuSample& b = imu[k + 1];
    ImuSample cur = imu[k];
    while (next_grid <= b.t) {
      if (next_grid > cur.t) {
        const ImuSample m = interpolateImu(imu[k], b, next_grid);
        step(cur, m);
        cur = m;
      }
      at_grid(next_grid);
      next_grid += period;
    }
    if (b.t > cur.t) step(cur, b);
    after_sample(b.t);
  }
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

ImoRunOutput runImoFilter(const std::vector<ImuSample>& imu, const NavState& init,
                          const ImoRunOptions& options, const DisplacementSource& source,
                          const std::function<void(Timestamp)>& on_progress) {
  checkRunOptions(options);
  const std::size_t k0 = startIndex(imu, init.t);
  const Timestamp period = fromSeconds(1.0 / options.update_rate_hz);
  const Timestamp window = fromSeconds(options.window_s);
  const auto window_clones = static_cast<std::size_t>(std::llround(options.window_s * options.update_rate_hz));
  const Mat3 fixed_cov = options.measurement_sigma.cwiseAbs2().asDiagonal();

  ImoRunOutput out;
  out.states.reserve(imu.size() - k0);  // growing it costs reallocation and page faults per step
  ImoFilter filter(options.filter);
  filter.initialize(nominalFrom(init));
  // Gyro integration since the start (filter bias at each step): the relative rotation used to
  // carry a clone's rotation across a network window. Updates do not touch it.
  Quat gamma = Quat::Identity();
  const Vec3 init_bg = filter.state().bg, init_ba = filter.state().ba;
  RotationHistory history;
  history.add(init.t, gamma);
  filter.addClone();
  out.states.push_back(navFrom(filter.state()));

  auto step = [&](const ImuSample& from, const ImuSample& to) {
    // Release propagation: the interval's newer sample held over it (zero-order hold).
    const bool hold = options.filter.release_propagation;
    const Vec3 gyro = hold ? to.gyro : Vec3(0.5 * (from.gyro + to.gyro));
    const Vec3 accel = hold ? to.accel : Vec3(0.5 * (from.accel + to.accel));
    const Vec3& bg = options.initial_window_biases ? init_bg : filter.state().bg;
    gamma = (gamma * quatExp((gyro - bg) * secondsBetween(from.t, to.t))).normalized();
    filter.propagate(gyro, accel, to.t);
    history.add(to.t, gamma);
  };

  double grid_s = 0.0;  // clone, source, update, marginalization
  auto at_grid = [&](Timestamp t_end) {
    const double t_grid = Clock::now();
    filter.addClone();
    const Timestamp t_begin = t_end - window;
    const int i = filter.findClone(t_begin);
    if (i < 0) {  // not one window of clones yet
      while (filter.clones().size() > window_clones + 1) filter.marginalizeClone(0);
      grid_s += secondsSince(t_grid);
      return;
    }
    const int j = static_cast<int>(filter.clones().size()) - 1;
    const double t_source = Clock::now();
    DisplacementRequest request = windowRequest(filter, history, i, t_begin, t_end);
    if (options.initial_window_biases) {
      request.gyro_bias = init_bg;
      request.accel_bias = init_ba;
    }
    const std::optional<DisplacementEstimate> est = source(request);
    out.source_s += secondsSince(t_source);
    if (!est) {
      ++out.no_measurement;
    } else {
      const RelativePositionMeasurement m = displacementMeasurement(
          *est, i, j, options.use_source_covariance ? est->covariance : fixed_cov);
      if (filter.update(m) == UpdateOutcome::kApplied) ++out.updates;
      else ++out.rejected;
    }
    while (!filter.clones().empty() && filter.clones().front().t <= t_begin)
      filter.marginalizeClone(0);
    history.dropBefore(filter.clones().front().t);
    grid_s += secondsSince(t_grid);
  };

  auto after_sample = [&](Timestamp t) {
    out.states.push_back(navFrom(filter.state()));
    if (on_progress) on_progress(t);
  };
  const double t_run = Clock::now();
  walkImu(imu, k0, period, step, at_grid, after_sample);
  out.propagation_s = secondsSince(t_run) - grid_s;  // with the per-sample state output
  out.update_s = grid_s - out.source_s;
  return out;
}

ImoRunOutput runNetworkOnly(const std::vector<ImuSample>& imu, const NavState& init,
                            const ImoRunOptions& options, const DisplacementSource& source,
                            const std::function<void(Timestamp)>& on_progress) {
  checkRunOptions(options);
  const std::size_t k0 = startIndex(imu, init.t);
  const Timestamp period = fromSeconds(1.0 / options.update_rate_hz);
  const Timestamp window = fromSeconds(options.window_s);

  ImoRunOutput out;
  ImoNominalState x = nominalFrom(init);  // dead reckoning: orientation, first window
  RotationHistory history;
  history.add(x.t, Quat(x.R));
  std::deque<std::pair<Timestamp, Vec3>> grid_positions{{x.t, x.p}};
  Vec3 last_velocity = x.v;
  out.states.push_back(navFrom(x));

  auto step = [&](const ImuSample& from, const ImuSample& to) {
    x = propagateStep(x, 0.5 * (from.gyro + to.gyro), 0.5 * (from.accel + to.accel),
                      secondsBetween(from.t, to.t), options.filter.gravity)
            .state;
    x.t = to.t;
    history.add(to.t, Quat(x.R));
  };

  auto at_grid = [&](Timestamp t) {
    Vec3 p = x.p;
    if (t - init.t >= window) {
      DisplacementRequest request;
      request.t_begin = t - window;
      request.t_end = t;
      request.world_from_body = [&history](Timestamp tt) { return history.at(tt); };
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
        p = grid_positions.back().second + last_velocity * secondsBetween(grid_positions.back().first, t);
        ++out.no_measurement;
      }
      grid_positions.pop_front();
    }
    grid_positions.emplace_back(t, p);
    NavState s = navFrom(x);
    s.t = t;
    s.T_WB = Pose(x.R, p);
    s.v_W = last_velocity;
    out.states.push_back(s);
  };

  auto after_sample = [&](Timestamp t) {
    history.dropBefore(t - window - period);
    if (on_progress) on_progress(t);
  };
  const double t_run = Clock::now();
  walkImu(imu, k0, period, step, at_grid, after_sample);
  out.propagation_s = secondsSince(t_run) - out.source_s;  // with concatenation and output
  return out;
}

}  // namespace hdvio::imo
