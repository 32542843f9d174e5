#pragma once
// A smooth 3-D trajectory with closed-form position, velocity, acceleration, attitude and body
// rates, and the noise-free IMU it produces (specific force and gyro in the body frame).
#include <cmath>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"

namespace hdvio::imo::testing {

struct TrajectoryPoint {
  Vec3 p, v, a;  // world
  Mat3 R;        // world_from_body
  Vec3 omega;    // body rate
};

// Lissajous-like flight (~2-3 m/s) with roll/pitch/yaw oscillations: R = Exp(theta(t)).
inline TrajectoryPoint trajectoryAt(double t) {
  const double w = 0.8;
  TrajectoryPoint s;
  s.p = Vec3(3.0 * std::sin(w * t), 2.0 * std::cos(1.3 * w * t), 0.5 * std::sin(2.0 * w * t));
  s.v = Vec3(3.0 * w * std::cos(w * t), -2.6 * w * std::sin(1.3 * w * t), w * std::cos(2.0 * w * t));
  s.a = Vec3(-3.0 * w * w * std::sin(w * t), -3.38 * w * w * std::cos(1.3 * w * t),
             -2.0 * w * w * std::sin(2.0 * w * t));
  const Vec3 theta(0.3 * std::sin(1.1 * t), 0.2 * std::cos(0.7 * t), 0.5 * t);
  const Vec3 theta_dot(0.33 * std::cos(1.1 * t), -0.14 * std::sin(0.7 * t), 0.5);
  s.R = so3Exp(theta);
  s.omega = rightJacobian(theta) * theta_dot;  // R^T dR/dt for R = Exp(theta)
  return s;
}

inline ImuSample imuAt(double t, Timestamp stamp) {
  const TrajectoryPoint s = trajectoryAt(t);
  return {stamp, s.omega, s.R.transpose() * (s.a - gravityWorld())};
}

// Noise-free IMU at rate_hz over [0, duration] (stamps in ns from 0).
inline std::vector<ImuSample> simulateImu(double rate_hz, double duration_s) {
  std::vector<ImuSample> imu;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  for (int k = 0; k <= n; ++k) {
    const Timestamp t = fromSeconds(k / rate_hz);
    imu.push_back(imuAt(toSeconds(t), t));
  }
  return imu;
}

}  // namespace hdvio::imo::testing
