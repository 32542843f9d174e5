#pragma once
// A flight resampled onto one uniform time grid: the network's inputs (thrust, gyro) and the
// ground truth the trainer supervises with (p, q, v) and the evaluator compares against
// (measured total force). Built from any hdvio::Sequence, so every dataset reader feeds it.
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::learned {

struct FlightSamples {
  std::string name;
  double rate_hz = 0.0;
  std::vector<Timestamp> t;
  std::vector<Vec3> thrust;  // mass-normalized collective thrust, body frame, m/s^2
  std::vector<Vec3> gyro;    // body frame, rad/s, ground-truth gyro bias removed when known
  std::vector<Vec3> p_W;     // ground-truth position, world
  std::vector<Quat> q_WB;    // ground-truth attitude
  std::vector<Vec3> v_W;     // ground-truth velocity, world
  // Measured total (thrust + aerodynamic) mass-normalized force in the body frame = the
  // accelerometer's specific force minus its known bias. Empty if the sequence has no IMU.
  std::vector<Vec3> force;

  std::size_t size() const { return t.size(); }
  // Samples [begin, end) as a new flight (for train/validation splits).
  FlightSamples slice(std::size_t begin, std::size_t end) const;
};

struct ResampleOptions {
  double rate_hz = 100.0;
  // Velocity from central differences of positions when the sequence has none.
  bool velocity_from_positions = true;
};

// Interpolates thrust (from Sequence::thrust or rotor speeds with the rotor calibration), IMU
// and ground truth (linear; slerp for attitude) on the grid covering the span all of them
// share. Throws InputError (naming the sequence) when a stream is missing or the span is
// shorter than one second.
FlightSamples resampleFlight(const Sequence& sequence, const ResampleOptions& options = {});

// Mass-normalized thrust of one rotor sample: thrust_coefficient / mass * sum(w^2) * axis.
Vec3 thrustFromRotors(const RotorCalibration& calibration, const Eigen::Vector4d& speeds);

}  // namespace hdvio::learned
