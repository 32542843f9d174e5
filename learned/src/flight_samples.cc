#include "hdvio/learned/flight_samples.h"

#include <algorithm>
#include <cmath>

#include "hdvio/core/error.h"

namespace hdvio::learned {
namespace {

// Linear interpolation of a time-ordered stream at t (t within the stream's span).
template <class Sample, class Get>
auto interpolate(const std::vector<Sample>& s, Timestamp t, Get get) {
  const auto hi = std::lower_bound(s.begin(), s.end(), t,
                                   [](const Sample& a, Timestamp v) { return a.t < v; });
  if (hi == s.begin()) return get(*hi);
  if (hi == s.end()) return get(s.back());
  const auto lo = hi - 1;
  const double a = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  return decltype(get(*lo))((1.0 - a) * get(*lo) + a * get(*hi));
}

std::size_t upperIndex(const std::vector<GroundTruthState>& s, Timestamp t) {
  return static_cast<std::size_t>(
      std::lower_bound(s.begin(), s.end(), t,
                       [](const GroundTruthState& a, Timestamp v) { return a.t < v; }) -
      s.begin());
}

Quat slerpAt(const std::vector<GroundTruthState>& s, Timestamp t) {
  const std::size_t hi = upperIndex(s, t);
  if (hi == 0) return s.front().T_WB.q;
  if (hi >= s.size()) return s.back().T_WB.q;
  const auto& a = s[hi - 1];
  const auto& b = s[hi];
  const double f = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return a.T_WB.q.slerp(f, b.T_WB.q).normalized();
}

template <class Sample>
void requireStream(const Sequence& seq, const std::vector<Sample>& s, const char* what) {
  if (s.size() < 2) {
    throw InputError(seq.source.empty() ? seq.name : seq.source, 0,
                     std::string("sequence has no ") + what + " (needed for the learned model)");
  }
}

}  // namespace

Vec3 thrustFromRotors(const RotorCalibration& c, const Eigen::Vector4d& speeds) {
  return c.thrust_coefficient / c.mass * speeds.squaredNorm() * c.thrust_axis;
}

FlightSamples FlightSamples::slice(std::size_t begin, std::size_t end) const {
  FlightSamples f;
  f.name = name;
  f.rate_hz = rate_hz;
  end = std::min(end, size());
  auto cut = [&](const auto& v) {
    using V = std::decay_t<decltype(v)>;
    return v.empty() ? V{} : V(v.begin() + static_cast<long>(begin), v.begin() + static_cast<long>(end));
  };
  f.t = cut(t);
  f.thrust = cut(thrust);
  f.gyro = cut(gyro);
  f.p_W = cut(p_W);
  f.q_WB = cut(q_WB);
  f.v_W = cut(v_W);
  f.force = cut(force);
  return f;
}

FlightSamples resampleFlight(const Sequence& seq, const ResampleOptions& options) {
  const std::string where = seq.source.empty() ? seq.name : seq.source;
  requireStream(seq, seq.imu, "IMU samples");
  requireStream(seq, seq.groundtruth, "ground truth");
  std::vector<ThrustSample> thrust = seq.thrust;
  if (thrust.empty()) {
    if (seq.rotor.empty() || !seq.rotor_calibration || seq.rotor_calibration->mass <= 0.0 ||
        seq.rotor_calibration->thrust_coefficient <= 0.0) {
      throw InputError(where, 0,
                       "sequence has neither thrust nor rotor speeds with a thrust coefficient "
                       "(identify one with hdvio_thrust_id)");
    }
    for (const auto& r : seq.rotor) thrust.push_back({r.t, thrustFromRotors(*seq.rotor_calibration, r.speeds)});
  }
  requireStream(seq, thrust, "thrust samples");

  const Timestamp t0 = std::max({seq.imu.front().t, thrust.front().t, seq.groundtruth.front().t});
  const Timestamp t1 = std::min({seq.imu.back().t, thrust.back().t, seq.groundtruth.back().t});
  if (t1 - t0 < kNanosPerSecond) {
    throw InputError(where, 0, "IMU, thrust and ground truth overlap for less than one second");
  }
  FlightSamples f;
  f.name = seq.name;
  f.rate_hz = options.rate_hz;
  const double step_ns = 1e9 / options.rate_hz;
  const auto n = static_cast<std::size_t>(std::floor(static_cast<double>(t1 - t0) / step_ns)) + 1;
  const bool gt_velocity =
      std::all_of(seq.groundtruth.begin(), seq.groundtruth.end(), [](const auto& g) { return g.has_velocity; });
  const bool gt_biases =
      std::all_of(seq.groundtruth.begin(), seq.groundtruth.end(), [](const auto& g) { return g.has_biases; });
  if (!gt_velocity && !options.velocity_from_positions) {
    throw InputError(where, 0, "ground truth has no velocity");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const Timestamp t = t0 + static_cast<Timestamp>(std::llround(k * step_ns));
    f.t.push_back(t);
    f.thrust.push_back(interpolate(thrust, t, [](const ThrustSample& s) -> Vec3 { return s.thrust; }));
    Vec3 gyro = interpolate(seq.imu, t, [](const ImuSample& s) -> Vec3 { return s.gyro; });
    Vec3 accel = interpolate(seq.imu, t, [](const ImuSample& s) -> Vec3 { return s.accel; });
    if (gt_biases) {
      gyro -= interpolate(seq.groundtruth, t, [](const GroundTruthState& s) -> Vec3 { return s.gyro_bias; });
      accel -= interpolate(seq.groundtruth, t, [](const GroundTruthState& s) -> Vec3 { return s.accel_bias; });
    }
    f.gyro.push_back(gyro);
    f.force.push_back(accel);
    f.p_W.push_back(interpolate(seq.groundtruth, t, [](const GroundTruthState& s) -> Vec3 { return s.T_WB.p; }));
    f.q_WB.push_back(slerpAt(seq.groundtruth, t));
    if (gt_velocity) {
      f.v_W.push_back(interpolate(seq.groundtruth, t, [](const GroundTruthState& s) -> Vec3 { return s.v_W; }));
    }
  }
  if (!gt_velocity) {
    f.v_W.assign(n, Vec3::Zero());
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t a = k == 0 ? 0 : k - 1;
      const std::size_t b = std::min(n - 1, k + 1);
      f.v_W[k] = (f.p_W[b] - f.p_W[a]) / ((b - a) / options.rate_hz);
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!f.thrust[k].allFinite() || !f.gyro[k].allFinite() || !f.p_W[k].allFinite() ||
        !f.v_W[k].allFinite() || !f.q_WB[k].coeffs().allFinite()) {
      throw InputError(where, 0, "non-finite value in the resampled flight at t = " + std::to_string(f.t[k]) + " ns");
    }
  }
  return f;
}

}  // namespace hdvio::learned
