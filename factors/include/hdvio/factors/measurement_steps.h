#pragma once
// Turns time-stamped IMU / thrust samples into integration steps covering exactly [t_i, t_j].
//
// Every sample time inside the interval starts a new step; each measurement is linearly
// interpolated at both ends of a step and the two values are averaged (trapezoid rule), so
// samples at different rates (IMU 400 Hz, thrust 100 Hz) combine without zero-order-hold lag.
#include <functional>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/core/time.h"

namespace hdvio {

struct ImuStep {
  double dt = 0.0;  // s
  Vec3 gyro = Vec3::Zero();
  Vec3 accel = Vec3::Zero();
};

struct DynamicsStep {
  double dt = 0.0;  // s
  Vec3 gyro = Vec3::Zero();
  Vec3 accel = Vec3::Zero();           // only used by the VID-Fusion force mean
  Vec3 thrust = Vec3::Zero();          // mass-normalized collective thrust, body frame
  Vec3 residual_force = Vec3::Zero();  // learned residual force, body frame (0 if none)
};

// Residual force (body frame, m/s^2) at a time, e.g. a learned model's prediction.
using ResidualForceFn = std::function<Vec3(Timestamp)>;

// Throws InputError if the samples do not cover [t_i, t_j], are not strictly increasing in
// time, or hold non-finite values; t_j must be after t_i.
std::vector<ImuStep> imuSteps(const std::vector<ImuSample>& imu, Timestamp t_i, Timestamp t_j);
std::vector<DynamicsStep> dynamicsSteps(const std::vector<ImuSample>& imu,
                                        const std::vector<ThrustSample>& thrust, Timestamp t_i,
                                        Timestamp t_j,
                                        const ResidualForceFn& residual_force = nullptr);

}  // namespace hdvio
