#pragma once
// Where the IMO filter's relative-position measurements come from. The filter does not know
// about networks: a source gets the window and the filter's orientation over it and returns a
// displacement (learned network in apps/run, the thrust model below, ground truth in tests).
#include <functional>
#include <optional>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/time.h"

namespace hdvio::imo {

struct DisplacementRequest {
  Timestamp t_begin = 0;
  Timestamp t_end = 0;
  // The filter's orientation over [t_begin, t_end]: the begin clone's (updated) rotation times
  // the gyro integration since then (as in the IMO / TLIO releases). Valid during the call only.
  std::function<Quat(Timestamp)> world_from_body;
  Vec3 gyro_bias = Vec3::Zero();
  Vec3 accel_bias = Vec3::Zero();
  Vec3 velocity_begin = Vec3::Zero();  // the begin clone's velocity (world)
};

// Measures z = p(t_end) - p(t_begin) - velocity_coefficient * v(t_begin), world frame.
struct DisplacementEstimate {
  Vec3 z = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
  double velocity_coefficient = 0.0;  // s
};

// nullopt: no measurement for this window (e.g. sensor streams do not cover it).
using DisplacementSource =
    std::function<std::optional<DisplacementEstimate>(const DisplacementRequest&)>;

// The Model-EKF measurement (paper Eq. 2, p' = v, v' = R T + g with the mass-normalized
// collective thrust T), integrated over the window from the filter's velocity at its start:
// z = W v_begin + double integral of R(t) T(t) + g, a measurement of p_end - p_begin (c = 0)
// like the networks'. Thrust is interpolated linearly at the midpoint of each `step_s` step;
// R from the request. Covariance diag(sigma^2). (Measuring p_j - p_i - W v_i instead, with
// c = W, would carry no velocity information at all: the IMU propagation predicts the same
// double integral.)
DisplacementSource makeThrustModelSource(std::vector<ThrustSample> thrust, double step_s,
                                         const Vec3& sigma, const Vec3& gravity);

// Linear interpolation in a time-ordered thrust stream; nullopt outside its span.
std::optional<Vec3> thrustAt(const std::vector<ThrustSample>& thrust, Timestamp t);

}  // namespace hdvio::imo
