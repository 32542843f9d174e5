#include "hdvio/sim/environment.h"

#include <cmath>
#include <random>

#include "hdvio/core/sequence.h"

namespace hdvio::sim {

Series smoothWindow(const Series& t, double start, double end, double ramp) {
  const double w = ramp / 4.0;  // tanh goes from 0.12 to 0.88 of its step within +-w... ~ramp total
  return 0.5 * (tanh((t - start) / w) - tanh((t - end) / w));
}

WindField::WindField(const WindConfig& config, std::uint64_t seed) : config_(config) {
  std::mt19937_64 rng(seed * 104729 + 3);
  std::normal_distribution<double> freq(0.0, 1.0 / config_.gust_time_scale);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  constexpr int kGustFeatures = 24;
  for (int axis = 0; axis < 3; ++axis) {
    for (int m = 0; m < kGustFeatures; ++m) {
      gust_freq_[axis].push_back(freq(rng));
      gust_phase_[axis].push_back(phase(rng));
    }
  }
}

bool WindField::calm() const {
  return config_.steady.norm() == 0.0 && config_.jets.empty() && config_.gust_std == 0.0;
}

SVec3 WindField::velocity(const SVec3& p, const Series& t) const {
  SVec3 w(config_.steady.x(), config_.steady.y(), config_.steady.z());
  for (const JetConfig& jet : config_.jets) {
    // A fan: Gaussian cross-section around the axis, switched on in front of the fan,
    // decaying along the axis.
    const SVec3 u(jet.direction.x(), jet.direction.y(), jet.direction.z());
    const SVec3 x = p - SVec3(jet.origin.x(), jet.origin.y(), jet.origin.z());
    const Series axial = dot(x, u);
    const Series radial2 = dot(x, x) - axial * axial;
    const Series front = 0.5 * (1.0 + tanh(axial / 0.25));
    const Series profile = exp(-0.5 * radial2 / (jet.radius * jet.radius) -
                               0.5 * axial * axial / (jet.length * jet.length));
    w = w + u * (jet.speed * front * profile);
  }
  if (config_.gust_std > 0.0) {
    for (int axis = 0; axis < 3; ++axis) {
      const double amplitude = config_.gust_std * (axis == 2 ? 0.5 : 1.0) *
                               std::sqrt(2.0 / gust_freq_[axis].size());
      Series g;
      for (size_t m = 0; m < gust_freq_[axis].size(); ++m)
        g += cos(gust_freq_[axis][m] * t + gust_phase_[axis][m]);
      w[axis] += amplitude * g;
    }
  }
  return w;
}

SVec3 ExternalForces::force(const Series& t, const SVec3& acceleration) const {
  SVec3 f(0.0, 0.0, 0.0);
  const SVec3 g(0.0, 0.0, -kGravity);
  for (const ForceEventConfig& e : events_) {
    const Series window = smoothWindow(t, e.start, e.end, e.ramp);
    if (e.type == ForceEventConfig::Type::kPull) {
      f = f + SVec3(e.force.x(), e.force.y(), e.force.z()) * window;
    }
    if (e.type == ForceEventConfig::Type::kPayload) {
      f = f - (acceleration - g) * (window * (e.mass / vehicle_mass_));
    }
  }
  return f;
}

}  // namespace hdvio::sim
