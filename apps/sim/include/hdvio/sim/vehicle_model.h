#pragma once
// The flatness map: from flat outputs (position, yaw) and the environment to the full true
// state of the vehicle, with exact derivatives.
//
// Model (mass-normalized, body frame B = IMU frame):
//   specific force  s = R^T (a - g) = T e_z + f_drag + f_ext
//   f_drag = -D v_rel_B - c |v_rel| v_rel_B,   v_rel = v - wind(p, t)
// so the thrust axis e_z must be parallel to  a - g - R f_drag - f_ext_W. Drag depends on R,
// so R is the fixed point of  R <- attitude(a - g - R f_drag(R) - f_ext_W, yaw), iterated on
// Taylor series (the derivatives converge with the values). |v_rel| is smoothed as
// sqrt(|v_rel|^2 + eps^2), eps = 1 mm/s, so hover stays differentiable; the written drag uses
// the same formula, so thrust + drag + external = specific force holds to round-off.
#include <memory>

#include "hdvio/core/sequence.h"
#include "hdvio/sim/environment.h"
#include "hdvio/sim/trajectory.h"

namespace hdvio::sim {

struct TrueState {
  double time = 0.0;  // s since the start of the flight
  Vec3 p = Vec3::Zero(), v = Vec3::Zero(), a = Vec3::Zero();  // world
  Mat3 R = Mat3::Identity();                                   // body -> world
  Vec3 omega = Vec3::Zero(), omega_dot = Vec3::Zero();         // body
  Vec3 specific_force = Vec3::Zero();  // body, R^T (a - g)
  double thrust = 0.0;                 // true collective thrust along body z (m/s^2)
  double thrust_rate = 0.0;            // d thrust / dt
  Vec3 thrust_residual_xy = Vec3::Zero();  // body x/y part of s - drag - ext (should be ~0)
  Vec3 drag = Vec3::Zero();            // body
  Vec3 external = Vec3::Zero();        // body
  Vec3 wind = Vec3::Zero();            // world
};

class VehicleModel {
 public:
  explicit VehicleModel(const SimConfig& config);  // throws InputError for impossible flights

  TrueState evaluate(double time) const;

  // Rotor speeds (rad/s) producing collective thrust `collective` (m/s^2) and the torques
  // J omega_dot + omega x J omega of `state` (X layout, rotors 1..4 at +-45 deg / +-135 deg).
  // Sets *clamped when a rotor would need negative thrust.
  Eigen::Vector4d rotorSpeeds(const TrueState& state, double collective, bool* clamped) const;

  const Trajectory& trajectory() const { return trajectory_; }

 private:
  VehicleConfig vehicle_;
  Trajectory trajectory_;
  WindField wind_;
  ExternalForces forces_;
  Eigen::Matrix4d allocation_inverse_;
};

}  // namespace hdvio::sim
