#pragma once
// What the air and the world do to the vehicle: a wind field (steady + fan jets + gusts) and
// external force events (rope pulls, payloads), all smooth in time and space so the flatness
// map stays differentiable. Forces are mass-normalized (m/s^2), world frame.
#include <cstdint>
#include <vector>

#include "hdvio/sim/series.h"
#include "hdvio/sim/sim_config.h"

namespace hdvio::sim {

class WindField {
 public:
  WindField(const WindConfig& config, std::uint64_t seed);
  SVec3 velocity(const SVec3& position, const Series& t) const;  // m/s, world
  bool calm() const;

 private:
  WindConfig config_;
  // Gusts: random Fourier features of a squared-exponential process in time, per axis.
  std::vector<double> gust_freq_[3], gust_phase_[3];
};

class ExternalForces {
 public:
  ExternalForces(std::vector<ForceEventConfig> events, double vehicle_mass)
      : events_(std::move(events)), vehicle_mass_(vehicle_mass) {}
  // acceleration: the vehicle's world acceleration. A rigidly hanging payload of mass m_p
  // needs m_p (a - g) of the rotors' force, i.e. -(m_p / m) (a - g) per unit vehicle mass.
  SVec3 force(const Series& t, const SVec3& acceleration) const;

 private:
  std::vector<ForceEventConfig> events_;
  double vehicle_mass_;
};

// Smooth window: ~0 before start, ~1 between, ~0 after end; rise time ~ramp.
Series smoothWindow(const Series& t, double start, double end, double ramp);

}  // namespace hdvio::sim
