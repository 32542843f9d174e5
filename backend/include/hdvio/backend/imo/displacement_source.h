#pragma once
// Where the IMO filter's relative-position measurements come from. The filter does not know
// about networks: a source gets the window and the filter's orientation over it and returns a
// displacement (learned network in apps/run, the drag model of drag_model.h, ground truth in tests).
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

// Measures z = p(t_end) - p(t_begin) - C v(t_begin) - J dtheta(t_begin), world frame, with
// C = velocity_coefficient I + velocity_matrix, J = attitude_jacobian (all zero for networks).
struct DisplacementEstimate {
  Vec3 z = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
  double velocity_coefficient = 0.0;      // s
  Mat3 velocity_matrix = Mat3::Zero();    // s
  Mat3 attitude_jacobian = Mat3::Zero();  // m/rad
};

// nullopt: no measurement for this window (e.g. sensor streams do not cover it).
using DisplacementSource =
    std::function<std::optional<DisplacementEstimate>(const DisplacementRequest&)>;

// The Model-EKF measurement (thrust + drag model) is makeDragModelSource in drag_model.h.

// Linear interpolation in a time-ordered thrust stream; nullopt outside its span.
std::optional<Vec3> thrustAt(const std::vector<ThrustSample>& thrust, Timestamp t);

}  // namespace hdvio::imo
