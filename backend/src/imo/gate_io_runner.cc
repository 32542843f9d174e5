#include "hdvio/backend/imo/gate_io_runner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "hdvio/backend/imo/imo_run_support.h"

namespace hdvio::imo {
namespace {

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

void checkGateIoOptions(const GateIoOptions& options, const DisplacementSource& source) {
  if (options.fuse_displacements) {
    checkRunOptions(options.imo);
    if (!source) throw std::invalid_argument("gate_io: displacement fusion needs a source");
  }
  if (!(options.pixel_sigma > 0.0)) throw std::invalid_argument("gate_io: pixel sigma must be positive");
}

struct GateIoStepper::Impl {
  Impl(const GateIoOptions& o, const CameraModel& cam, const Pose& T, const NavState& init,
       const ImuSample& first, DisplacementSource src)
      : options(o), camera(cam), T_BC(T), source(std::move(src)), filter(o.imo.filter), prev(first),
        fuse(o.fuse_displacements),
        period(fuse ? fromSeconds(1.0 / o.imo.update_rate_hz) : 0),
        window(fuse ? fromSeconds(o.imo.window_s) : 0),
        window_clones(fuse ? static_cast<std::size_t>(std::llround(o.imo.window_s * o.imo.update_rate_hz)) : 0),
        fixed_cov(o.imo.measurement_sigma.cwiseAbs2().asDiagonal()),
        // 2-dof chi-square quantile in closed form: P(chi2_2 > q) = exp(-q / 2).
        corner_threshold(o.corner_gate_probability > 0.0 ? -2.0 * std::log(1.0 - o.corner_gate_probability) : -1.0),
        pixel_var(o.pixel_sigma * o.pixel_sigma) {
    filter.initialize(nominalFrom(init));
    out.states.push_back(navFrom(filter.state()));
    history.add(init.t, gamma);
    if (fuse) filter.addClone();
    next_grid = init.t + period;
  }
  void step(const ImuSample& from, const ImuSample& to);
  void gateUpdate(const GateFrame& frame);
  void displacementUpdate(Timestamp t_end);

  const GateIoOptions options;
  const CameraModel camera;
  const Pose T_BC;
  const DisplacementSource source;
  ImoFilter filter;
  ImuSample prev;  // the last sample stepped
  std::deque<GateFrame> frames;  // given, not yet applied
  const bool fuse;
  const Timestamp period, window;
  const std::size_t window_clones;
  const Mat3 fixed_cov;
  const double corner_threshold, pixel_var;
  Quat gamma = Quat::Identity();
  RotationHistory history;
  Timestamp next_grid = 0;
  double chi2_sum = 0.0;
  GateIoOutput out;
};

void GateIoStepper::Impl::step(const ImuSample& from, const ImuSample& to) {
  const double t0 = threadCpuSeconds();
  const Vec3 gyro = 0.5 * (from.gyro + to.gyro);
  const Vec3 accel = 0.5 * (from.accel + to.accel);
  if (fuse) {
    gamma = (gamma * quatExp((gyro - filter.state().bg) * secondsBetween(from.t, to.t))).normalized();
    history.add(to.t, gamma);
  }
  filter.propagate(gyro, accel, to.t);
  out.propagation_s += threadCpuSeconds() - t0;
}

void GateIoStepper::Impl::gateUpdate(const GateFrame& frame) {
  const double t0 = threadCpuSeconds();
  const int dim = kStateDim + kCloneDim * static_cast<int>(filter.clones().size());
  GateFrameMeasurement m = gateFrameMeasurement(camera, T_BC, filter.state(), frame.corners, dim);
  m.H = filter.jacobianInFilterConvention(m.H);
  if (corner_threshold > 0.0 && !m.used.empty()) m = dropOutlierCorners(m, filter.covariance(), pixel_var,
                                                                        corner_threshold, &out.corners_rejected);
  if (!m.used.empty()) {
    const MatX R = MatX::Identity(m.residual.size(), m.residual.size()) * pixel_var;
    const UpdateOutcome outcome = filter.updateGeneric(m.residual, m.H, R, options.gate_probability);
    chi2_sum += filter.lastMahalanobis() / static_cast<double>(m.residual.size());
    if (outcome == UpdateOutcome::kApplied) {
      ++out.frames_applied;
      out.corners_used += static_cast<long>(m.used.size());
    } else {
      ++out.frames_rejected;
    }
    out.mean_chi2_per_dof = chi2_sum / (out.frames_applied + out.frames_rejected);
  }
  out.gate_update_s += threadCpuSeconds() - t0;
}

void GateIoStepper::Impl::displacementUpdate(Timestamp t_end) {
  double t0 = threadCpuSeconds();
  filter.addClone();
  const Timestamp t_begin = t_end - window;
  const int i = filter.findClone(t_begin);
  if (i < 0) {
    while (filter.clones().size() > window_clones + 1) filter.marginalizeClone(0);
    out.displacement_update_s += threadCpuSeconds() - t0;
    return;
  }
  const DisplacementRequest request = windowRequest(filter, history, i, t_begin, t_end);
  out.displacement_update_s += threadCpuSeconds() - t0;
  t0 = threadCpuSeconds();
  const std::optional<DisplacementEstimate> est = source(request);
  out.source_s += threadCpuSeconds() - t0;
  t0 = threadCpuSeconds();
  if (!est) {
    ++out.no_displacement;
  } else {
    const RelativePositionMeasurement rm = displacementMeasurement(
        *est, i, static_cast<int>(filter.clones().size()) - 1,
        options.imo.use_source_covariance ? est->covariance : fixed_cov);
    if (filter.update(rm) == UpdateOutcome::kApplied) ++out.displacement_updates;
    else ++out.displacement_rejected;
  }
  while (!filter.clones().empty() && filter.clones().front().t <= t_begin) filter.marginalizeClone(0);
  history.dropBefore(filter.clones().front().t);
  out.displacement_update_s += threadCpuSeconds() - t0;
}

GateIoStepper::GateIoStepper(const GateIoOptions& options, const CameraModel& camera, const Pose& T_BC,
                             const NavState& init, const ImuSample& first, DisplacementSource source) {
  checkGateIoOptions(options, source);
  impl_ = std::make_unique<Impl>(options, camera, T_BC, init, first, std::move(source));
}

GateIoStepper::~GateIoStepper() = default;

void GateIoStepper::addFrame(const GateFrame& frame) {
  if (frame.t <= impl_->prev.t || (!impl_->frames.empty() && frame.t < impl_->frames.back().t)) return;
  impl_->frames.push_back(frame);
}

// The interval is split at the frame and grid times inside it; a frame and a grid time that
// coincide: the gate update first, so the clone carries it.
void GateIoStepper::addImu(const ImuSample& b) {
  Impl& s = *impl_;
  if (b.t <= s.prev.t) throw std::invalid_argument("gate_io: IMU samples must be strictly increasing");
  ImuSample cur = s.prev;
  while (true) {
    const Timestamp t_frame = !s.frames.empty() ? s.frames.front().t : b.t + 1;
    const Timestamp t_grid = s.fuse ? s.next_grid : b.t + 1;
    const Timestamp t_event = std::min(t_frame, t_grid);
    if (t_event > b.t) break;
    if (t_event > cur.t) {
      const ImuSample m = interpolateImu(s.prev, b, t_event);
      s.step(cur, m);
      cur = m;
    }
    if (t_frame == t_event) {
      s.gateUpdate(s.frames.front());
      s.frames.pop_front();
    } else {
      s.displacementUpdate(t_grid);
      s.next_grid += s.period;
    }
  }
  if (b.t > cur.t) s.step(cur, b);
  s.prev = b;
  s.out.states.push_back(navFrom(s.filter.state()));
}

Timestamp GateIoStepper::nextGridTime() const {
  return impl_->fuse ? impl_->next_grid : std::numeric_limits<Timestamp>::max();
}
NavState GateIoStepper::state() const { return navFrom(impl_->filter.state()); }
const GateIoOutput& GateIoStepper::output() const { return impl_->out; }
GateIoOutput& GateIoStepper::output() { return impl_->out; }

GateIoOutput runGateIo(const std::vector<ImuSample>& imu, const NavState& init,
                       const GateIoOptions& options, const CameraModel& camera, const Pose& T_BC,
                       const std::vector<GateFrame>& frames, const DisplacementSource& source,
                       const std::function<void(Timestamp)>& on_progress) {
  checkGateIoOptions(options, source);
  auto first = std::lower_bound(imu.begin(), imu.end(), init.t,
                                [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (first == imu.end() || first->t != init.t)
    throw std::invalid_argument("gate_io: the initial time is not an IMU sample time");
  GateIoStepper stepper(options, camera, T_BC, init, *first, source);
  auto frame_it = std::upper_bound(frames.begin(), frames.end(), init.t,
                                   [](Timestamp t, const GateFrame& f) { return t < f.t; });
  for (auto b = first + 1; b != imu.end(); ++b) {
    for (; frame_it != frames.end() && frame_it->t <= b->t; ++frame_it) stepper.addFrame(*frame_it);
    stepper.addImu(*b);
    if (on_progress) on_progress(b->t);
  }
  return std::move(stepper.output());
}

}  // namespace hdvio::imo
