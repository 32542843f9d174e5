#include "hdvio/sim/trajectory.h"

#include <cmath>
#include <random>
#include <sstream>

#include <Eigen/Dense>

#include "hdvio/core/error.h"

namespace hdvio::sim {
namespace {

SVec3 constant(const Vec3& v) { return SVec3(v.x(), v.y(), v.z()); }

std::string describe(const Vec3& v) {
  std::ostringstream s;
  s.precision(3);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

}  // namespace

Trajectory::Trajectory(const TrajectoryConfig& traj, const YawConfig& yaw, const SceneConfig& scene,
                       double duration, std::uint64_t seed)
    : traj_(traj), yaw_(yaw), duration_(duration) {
  if (traj_.type == TrajectoryType::kRandom) setupRandom(seed);
  if (traj_.type == TrajectoryType::kRace) setupRace();

  if (traj_.type == TrajectoryType::kHover) {
    omega_ = 0.0;
  } else {
    omega_ = traj_.type == TrajectoryType::kCircle ? traj_.max_speed / traj_.radius : 1.0;
    // Peak speed is linear in omega for a fixed range of s; the range grows with omega, so
    // iterate until the measured peak matches.
    for (int iter = 0; iter < 12; ++iter) {
      const double peak = measurePeakSpeed();
      if (!(peak > 1e-9)) {
        throw InputError("", 0, "trajectory: the '" + toString(traj_.type) + "' shape does not move");
      }
      const double ratio = traj_.max_speed / peak;
      omega_ *= ratio;
      if (std::abs(ratio - 1.0) < 1e-5) break;
    }
  }
  peak_speed_ = measurePeakSpeed();

  // The flight must stay inside the room with clearance (the renderer assumes it).
  const Vec3 lo = scene.room_min + Vec3::Constant(scene.min_clearance);
  const Vec3 hi = scene.room_max - Vec3::Constant(scene.min_clearance);
  for (double t = 0.0; t <= duration_ + 1e-9; t += 0.005) {
    const SVec3 p = position(Series(t));
    const Vec3 x(p.x.value(), p.y.value(), p.z.value());
    if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) {
      std::ostringstream s;
      s << "trajectory: position " << describe(x) << " at t = " << t
        << " s is outside the room " << describe(scene.room_min) << " .. "
        << describe(scene.room_max) << " minus clearance " << scene.min_clearance << " m";
      throw InputError("", 0, s.str());
    }
  }
}

void Trajectory::setupRandom(std::uint64_t seed) {
  // Random Fourier features: g(s) = sqrt(2/M) sum cos(f_m s + phi_m), f ~ N(0, 1), phi ~ U(0, 2pi)
  // approximates a unit-variance Gaussian process with squared-exponential kernel of length 1.
  std::mt19937_64 rng(seed * 7919 + 17);
  std::normal_distribution<double> freq(0.0, 1.0);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  for (int axis = 0; axis < 3; ++axis) {
    for (int m = 0; m < traj_.random_features; ++m) {
      rf_freq_[axis].push_back(freq(rng));
      rf_phase_[axis].push_back(phase(rng));
    }
  }
}

void Trajectory::setupRace() {
  // Closed periodic curve through the gate centres: von Mises kernel interpolation with nodes
  // uniform in s over [0, 2 pi). Kernel width ~ node spacing keeps it smooth without overshoot.
  const int n = static_cast<int>(traj_.gates.size());
  const double spacing = 2.0 * M_PI / n;
  kernel_kappa_ = 1.0 / (0.8 * spacing * 0.8 * spacing);
  node_s_.resize(n);
  node_mean_.setZero();
  for (int i = 0; i < n; ++i) {
    node_s_[i] = i * spacing;
    node_mean_ += traj_.gates[i].position / n;
  }
  Eigen::MatrixXd K(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) K(i, j) = std::exp(kernel_kappa_ * (std::cos(node_s_[i] - node_s_[j]) - 1.0));
  Eigen::MatrixXd Y(n, 3);
  for (int i = 0; i < n; ++i) Y.row(i) = (traj_.gates[i].position - node_mean_).transpose();
  const Eigen::MatrixXd W = K.colPivHouseholderQr().solve(Y);
  node_weight_.resize(n);
  for (int i = 0; i < n; ++i) node_weight_[i] = W.row(i).transpose();
}

Series Trajectory::ramp(const Series& t) const {
  const double T = traj_.ramp_time;
  if (T <= 0.0) return t;
  const double tau = T / 6.0, t0 = T / 2.0;
  return 0.5 * (t + tau * (logcosh((t - t0) / tau) - logcosh(Series(-t0 / tau))));
}

SVec3 Trajectory::shape(const Series& s) const {
  const Vec3& c = traj_.center;
  if (traj_.type == TrajectoryType::kHover) return constant(c);
  if (traj_.type == TrajectoryType::kCircle) {
    Series sn, cs;
    sincos(s, &sn, &cs);
    return {c.x() + traj_.radius * cs, c.y() + traj_.radius * sn,
            c.z() + traj_.height_amplitude * sin(2.0 * s)};
  }
  if (traj_.type == TrajectoryType::kLemniscate) {
    Series sn, cs;
    sincos(s, &sn, &cs);
    return {c.x() + traj_.extent.x() * sn, c.y() + traj_.extent.y() * sin(2.0 * s),
            c.z() + traj_.height_amplitude * cs};
  }
  if (traj_.type == TrajectoryType::kRandom) {
    SVec3 p;
    const double norm = std::sqrt(2.0 / traj_.random_features);
    for (int axis = 0; axis < 3; ++axis) {
      Series g;
      for (size_t m = 0; m < rf_freq_[axis].size(); ++m) g += cos(rf_freq_[axis][m] * s + rf_phase_[axis][m]);
      p[axis] = c[axis] + traj_.extent[axis] * tanh(norm * g);
    }
    return p;
  }
  // race
  SVec3 p = constant(node_mean_);
  for (size_t i = 0; i < node_s_.size(); ++i) {
    const Series k = exp(kernel_kappa_ * (cos(s - node_s_[i]) - 1.0));
    p = p + constant(node_weight_[i]) * k;
  }
  return p;
}

SVec3 Trajectory::position(const Series& t) const { return shape(omega_ * ramp(t)); }

Series Trajectory::yaw(const Series& t, const SVec3& p) const {
  if (yaw_.mode == YawMode::kFixed) return Series(yaw_.value);
  if (yaw_.mode == YawMode::kRate) return yaw_.value + yaw_.rate * ramp(t);
  if (yaw_.mode == YawMode::kOscillate) return yaw_.value + yaw_.amplitude * sin(2.0 * M_PI * yaw_.frequency * t);
  // forward: heading along the horizontal velocity (plus the configured offset)
  const SVec3 v = derivative(p);
  return yaw_.value + atan2(v.y, v.x);
}

std::vector<GateConfig> Trajectory::orientedGates() const {
  std::vector<GateConfig> gates = traj_.gates;
  for (size_t i = 0; i < gates.size() && i < node_s_.size(); ++i) {
    const SVec3 tangent = derivative(shape(Series::variable(node_s_[i])));
    gates[i].yaw = std::atan2(tangent.y.value(), tangent.x.value());
  }
  return gates;
}

double Trajectory::measurePeakSpeed() const {
  double peak = 0.0;
  for (double t = 0.0; t <= duration_ + 1e-9; t += 0.005) {
    const SVec3 v = derivative(position(Series::variable(t)));
    peak = std::max(peak, std::sqrt(dot(v, v).value()));
  }
  return peak;
}

}  // namespace hdvio::sim
