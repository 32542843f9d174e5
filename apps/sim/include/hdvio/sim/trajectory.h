#pragma once
// Flat outputs of a flight: position p(t) and yaw psi(t), smooth (C-infinity) analytic
// functions evaluated as Taylor series so every derivative is exact.
//
// Every shape is a curve c(s) of a path parameter s; time enters through a smooth speed ramp
// s(t) = omega * ramp(t) with ramp'(t) = 0.5 (1 + tanh((t - T/2) / (T/6))), T = ramp_time,
// so the flight starts almost at rest. omega is chosen so the peak speed over the configured
// duration equals max_speed.
#include <cstdint>
#include <vector>

#include "hdvio/sim/series.h"
#include "hdvio/sim/sim_config.h"

namespace hdvio::sim {

class Trajectory {
 public:
  // Throws InputError when the flight leaves the room (minus clearance) or cannot reach the
  // requested speed.
  Trajectory(const TrajectoryConfig& traj, const YawConfig& yaw, const SceneConfig& scene,
             double duration, std::uint64_t seed);

  SVec3 position(const Series& t) const;                  // world, m
  Series yaw(const Series& t, const SVec3& position) const;  // rad
  double peakSpeed() const { return peak_speed_; }         // measured on a 5 ms grid
  double pathRate() const { return omega_; }               // omega, path parameter per second
  // race: the configured gates, each turned to face the flight direction through it.
  std::vector<GateConfig> orientedGates() const;

 private:
  SVec3 shape(const Series& s) const;
  Series ramp(const Series& t) const;
  double measurePeakSpeed() const;
  void setupRandom(std::uint64_t seed);
  void setupRace();

  TrajectoryConfig traj_;
  YawConfig yaw_;
  double duration_;
  double omega_ = 1.0;
  double peak_speed_ = 0.0;
  // random: per axis, Fourier features (frequency, phase) of a unit-variance squared-exponential GP
  std::vector<double> rf_freq_[3], rf_phase_[3];
  // race: periodic kernel interpolation through gate approach points
  std::vector<double> node_s_;
  std::vector<Vec3> node_weight_;
  Vec3 node_mean_ = Vec3::Zero();
  double kernel_kappa_ = 1.0;
};

}  // namespace hdvio::sim
