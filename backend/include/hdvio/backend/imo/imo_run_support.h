#pragma once
// What the IMO EKF driver and its updaters (imo_stepper.h, imo_updaters.h) share:
// conversions between the filter's nominal state and NavState, IMU interpolation at split
// times and the gyro-integrated rotation history for network windows (their CPU clock is
// core/thread_clock.h).
#include <deque>
#include <utility>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/backend/imo/imo_propagation.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/thread_clock.h"

namespace hdvio::imo {

ImoNominalState nominalFrom(const NavState& s);
NavState navFrom(const ImoNominalState& x);

// Linear interpolation of gyro and accel between two samples at a ≤ t ≤ b.
ImuSample interpolateImu(const ImuSample& a, const ImuSample& b, Timestamp t);

// Rotations at the times the filter passed through, for the network windows; slerp between.
class RotationHistory {
 public:
  void add(Timestamp t, const Quat& q);
  Quat at(Timestamp t) const;  // clamped to the first / last entry outside the span
  // Keeps the last entry at or before t (and everything after).
  void dropBefore(Timestamp t);

 private:
  std::deque<std::pair<Timestamp, Quat>> entries_;
};

// The displacement request for the window [t_begin, t_end] that starts at clone i: orientation
// = clone i's rotation times the gyro integration since it (no jumps from updates inside the
// window), the filter's biases and clone i's velocity. `history` must outlive the request.
DisplacementRequest windowRequest(const ImoFilter& filter, const RotationHistory& history,
                                  int clone_i, Timestamp t_begin, Timestamp t_end);

// The relative-position measurement of an estimate between clones i and j.
RelativePositionMeasurement displacementMeasurement(const DisplacementEstimate& est, int clone_i,
                                                    int clone_j, const Mat3& covariance);

}  // namespace hdvio::imo
