#pragma once
// Identifies the rotor thrust coefficient from flight data, for rotor-speed datasets that do
// not publish one (DIDO): along the thrust axis the accelerometer's specific force is
// (C_T / m) * sum(w_i^2), optionally minus linear drag d_z * v_z (body velocity). Linear least
// squares over all samples; hover-only data determines C_T/m as well as aggressive flight.
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::learned {

struct ThrustFitOptions {
  Vec3 thrust_axis = Vec3::UnitZ();  // body (IMU) frame; the sign is checked, see below
  bool fit_linear_drag = false;      // also fit d_x, d_y, d_z (needs ground-truth velocity)
  double min_rotor_speed = 1.0;      // rad/s; samples with all rotors slower are skipped (on ground)
};

struct ThrustFit {
  double c_over_m = 0.0;          // C_T / m, m s^-2 per (rad/s)^2
  Vec3 thrust_axis = Vec3::UnitZ();  // the axis used; flipped if the data says thrust points along -axis
  Vec3 linear_drag = Vec3::Zero();   // d (1/s): drag = -d .* v_body, zero unless fitted
  std::size_t samples = 0;
  double rmse_axis = 0.0;         // m/s^2, residual along the thrust axis
  double rmse_total = 0.0;        // m/s^2, |a - model| over all three axes
  // C_T in N s^2 rad^-2 for a given mass.
  double thrustCoefficient(double mass) const { return c_over_m * mass; }
};

// Pairs every rotor sample with the linearly interpolated specific force (IMU accel minus
// its ground-truth bias when known) and, for drag, ground-truth body velocity. Throws
// InputError when the sequence lacks rotor speeds or IMU, or fewer than 100 samples remain.
ThrustFit fitThrust(const Sequence& sequence, const ThrustFitOptions& options = {});

// One fit over several flights (their clocks may overlap: each is shifted to start after the
// previous one ends), using the rotor samples in [begin, end) of each flight's rotor stream.
// This is the thrust model of a cross-validation fold: fitted on its training flights only.
ThrustFit fitThrustJointly(const std::vector<Sequence>& flights, const ThrustFitOptions& options = {},
                           double begin = 0.0, double end = 1.0);

// The fitted model's mass-normalized force for one rotor sample and body velocity.
Vec3 predictFittedForce(const ThrustFit& fit, const Eigen::Vector4d& speeds, const Vec3& v_body);

}  // namespace hdvio::learned
