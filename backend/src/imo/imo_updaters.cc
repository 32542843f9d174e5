#include "hdvio/backend/imo/imo_updaters.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

namespace hdvio::imo {
namespace {

// Stage times are this thread's CPU time (the cost on one core, independent of machine load).
// Reading that clock costs ~1.4 us on the VM of docs/benchmarks.md, so it is read around each
// update, never per IMU step.
double now() { return threadCpuSeconds(); }

std::size_t windowClones(const ImoRunOptions& o) {
  return static_cast<std::size_t>(std::llround(o.window_s * o.update_rate_hz));
}

// Keeps the corners whose own 2-dof innovation r_i' S_i^-1 r_i is below the threshold.
GateFrameMeasurement dropOutlierCorners(const GateFrameMeasurement& m, const MatX& P, double pixel_var,
                                        double threshold, long* rejected) {
  std::vector<int> keep;
  for (std::size_t k = 0; k < m.used.size(); ++k) {
    const auto H = m.H.middleRows<2>(2 * static_cast<int>(k));
    const Eigen::Matrix2d S = H * P * H.transpose() + pixel_var * Eigen::Matrix2d::Identity();
    const Eigen::Vector2d r = m.residual.segment<2>(2 * static_cast<int>(k));
    if (r.dot(S.ldlt().solve(r)) <= threshold) keep.push_back(static_cast<int>(k));
  }
  *rejected += static_cast<long>(m.used.size() - keep.size());
  if (keep.size() == m.used.size()) return m;
  GateFrameMeasurement out;
  out.residual.resize(2 * static_cast<int>(keep.size()));
  out.H.resize(2 * static_cast<int>(keep.size()), m.H.cols());
  for (std::size_t j = 0; j < keep.size(); ++j) {
    out.residual.segment<2>(2 * static_cast<int>(j)) = m.residual.segment<2>(2 * keep[j]);
    out.H.middleRows<2>(2 * static_cast<int>(j)) = m.H.middleRows<2>(2 * keep[j]);
    out.used.push_back(m.used[keep[j]]);
  }
  return out;
}

}  // namespace

// ---- DisplacementUpdater

DisplacementUpdater::DisplacementUpdater(const ImoRunOptions& options, DisplacementSource source)
    : options_((checkRunOptions(options), options)),
      source_(std::move(source)),
      period_(fromSeconds(1.0 / options.update_rate_hz)),
      window_(fromSeconds(options.window_s)),
      window_clones_(windowClones(options)),
      fixed_cov_(options.measurement_sigma.cwiseAbs2().asDiagonal()) {
  if (!source_) throw std::invalid_argument("IMO run: the displacement update needs a source");
}

void DisplacementUpdater::start(ImoFilter& filter, ImoRunOutput&) {
  init_bg_ = filter.state().bg;
  init_ba_ = filter.state().ba;
  history_.add(filter.state().t, gamma_);
  filter.addClone();
  next_grid_ = filter.state().t + period_;
}

void DisplacementUpdater::propagated(const ImoFilter& filter, const Vec3& gyro, Timestamp t_from,
                                     Timestamp t_to) {
  const Vec3& bg = options_.initial_window_biases ? init_bg_ : filter.state().bg;
  gamma_ = (gamma_ * quatExp((gyro - bg) * secondsBetween(t_from, t_to))).normalized();
  history_.add(t_to, gamma_);
}

// The source runs before the clone at t_end is added, which it does not read (clone i, the
// biases and the rotation history are unchanged by cloning).
void DisplacementUpdater::update(ImoFilter& filter, ImoRunOutput& out) {
  const double t_grid = now();
  const Timestamp t_end = next_grid_;
  const Timestamp t_begin = t_end - window_;
  next_grid_ += period_;
  const int i = filter.findClone(t_begin);
  if (i < 0) {  // not one window of clones yet
    filter.addClone();
    while (filter.clones().size() > window_clones_ + 1) filter.marginalizeClone(0);
    out.update_s += now() - t_grid;
    return;
  }
  DisplacementRequest request = windowRequest(filter, history_, i, t_begin, t_end);
  if (options_.initial_window_biases) {
    request.gyro_bias = init_bg_;
    request.accel_bias = init_ba_;
  }
  const std::optional<DisplacementEstimate> est = source_(request);
  const double t_update = now();
  out.source_s += t_update - t_grid;
  filter.addClone();
  const int j = static_cast<int>(filter.clones().size()) - 1;
  if (!est) {
    ++out.no_measurement;
  } else {
    const RelativePositionMeasurement meas = displacementMeasurement(
        *est, i, j, options_.use_source_covariance ? est->covariance : fixed_cov_);
    const bool applied = filter.update(meas) == UpdateOutcome::kApplied;
    if (applied) ++out.updates;
    else ++out.rejected;
    out.innovations.push_back({t_end, filter.lastInnovation(), applied});
  }
  while (!filter.clones().empty() && filter.clones().front().t <= t_begin) filter.marginalizeClone(0);
  history_.dropBefore(filter.clones().front().t);
  out.update_s += now() - t_update;
}

// ---- DisplacementConcatenation

DisplacementConcatenation::DisplacementConcatenation(const ImoRunOptions& options, DisplacementSource source)
    : options_((checkRunOptions(options), options)),
      source_(std::move(source)),
      period_(fromSeconds(1.0 / options.update_rate_hz)),
      window_(fromSeconds(options.window_s)) {
  if (!source_) throw std::invalid_argument("network-only needs a displacement source");
}

void DisplacementConcatenation::start(ImoFilter& filter, ImoRunOutput&) {
  const ImoNominalState& x = filter.state();
  init_t_ = x.t;
  history_.add(x.t, Quat(x.R));
  grid_positions_.emplace_back(x.t, x.p);
  last_velocity_ = x.v;
  next_grid_ = x.t + period_;
}

void DisplacementConcatenation::propagated(const ImoFilter& filter, const Vec3&, Timestamp, Timestamp t_to) {
  history_.add(t_to, Quat(filter.state().R));
  history_.dropBefore(t_to - window_ - period_);
}

void DisplacementConcatenation::update(ImoFilter& filter, ImoRunOutput& out) {
  const ImoNominalState& x = filter.state();
  const Timestamp t_end = next_grid_;
  next_grid_ += period_;
  Vec3 p = x.p;
  if (t_end - init_t_ >= window_) {
    DisplacementRequest request;
    request.t_begin = t_end - window_;
    request.t_end = t_end;
    request.world_from_body = [this](Timestamp tt) { return history_.at(tt); };
    request.gyro_bias = x.bg;
    request.accel_bias = x.ba;
    const double t0 = now();
    const std::optional<DisplacementEstimate> est = source_(request);
    out.source_s += now() - t0;
    if (est && (est->velocity_coefficient != 0.0 || !est->velocity_matrix.isZero(0.0) ||
                !est->attitude_jacobian.isZero(0.0)))
      throw std::invalid_argument("network-only needs a pure displacement source");
    const Vec3 p_begin = grid_positions_.front().second;  // at t - window
    if (est) {
      p = p_begin + est->z;
      last_velocity_ = est->z / options_.window_s;
      ++out.updates;
    } else {
      p = grid_positions_.back().second + last_velocity_ * secondsBetween(grid_positions_.back().first, t_end);
      ++out.no_measurement;
    }
    grid_positions_.pop_front();
  }
  grid_positions_.emplace_back(t_end, p);
  NavState s = navFrom(x);
  s.t = t_end;
  s.T_WB = Pose(x.R, p);
  s.v_W = last_velocity_;
  out.states.push_back(s);
}

// ---- GateCornerUpdater

GateCornerUpdater::GateCornerUpdater(const GateCornerOptions& options, const CameraModel& camera,
                                     const Pose& T_BC)
    : options_(options),
      camera_(camera),
      T_BC_(T_BC),
      // 2-dof chi-square quantile in closed form: P(chi2_2 > q) = exp(-q / 2).
      corner_threshold_(options.corner_gate_probability > 0.0
                            ? -2.0 * std::log(1.0 - options.corner_gate_probability)
                            : -1.0),
      pixel_var_(options.pixel_sigma * options.pixel_sigma) {
  if (!(options.pixel_sigma > 0.0)) throw std::invalid_argument("gate_io: pixel sigma must be positive");
}

void GateCornerUpdater::addFrame(const GateFrame& frame) {
  if (frame.t <= stepped_ || (!frames_.empty() && frame.t < frames_.back().t)) return;
  frames_.push_back(frame);
}

void GateCornerUpdater::start(ImoFilter& filter, ImoRunOutput&) { stepped_ = filter.state().t; }

void GateCornerUpdater::update(ImoFilter& filter, ImoRunOutput& out) {
  const double t0 = now();
  const GateFrame frame = std::move(frames_.front());
  frames_.pop_front();
  const int dim = kStateDim + kCloneDim * static_cast<int>(filter.clones().size());
  GateFrameMeasurement m = gateFrameMeasurement(camera_, T_BC_, filter.state(), frame.corners, dim);
  m.H = filter.jacobianInFilterConvention(m.H);
  if (corner_threshold_ > 0.0 && !m.used.empty())
    m = dropOutlierCorners(m, filter.covariance(), pixel_var_, corner_threshold_, &out.corners_rejected);
  if (!m.used.empty()) {
    const MatX R = MatX::Identity(m.residual.size(), m.residual.size()) * pixel_var_;
    const UpdateOutcome outcome = filter.updateGeneric(m.residual, m.H, R, options_.gate_probability);
    chi2_sum_ += filter.lastMahalanobis() / static_cast<double>(m.residual.size());
    if (outcome == UpdateOutcome::kApplied) {
      ++out.frames_applied;
      out.corners_used += static_cast<long>(m.used.size());
    } else {
      ++out.frames_rejected;
    }
    out.mean_chi2_per_dof = chi2_sum_ / (out.frames_applied + out.frames_rejected);
  }
  out.gate_update_s += now() - t0;
}

}  // namespace hdvio::imo
