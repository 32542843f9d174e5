#pragma once
// A change of the visual-inertial window's gauge: a rotation about world z plus a translation,
// the directions no relative measurement sees (camera, IMU with gravity along z, dynamics in
// the world frame). Applied to every variable of a window it leaves every factor unchanged
// but the priors, which hold the gauge.
#include "hdvio/core/lie.h"
#include "hdvio/core/values.h"

namespace hdvio {

struct GaugeTransform {
  Mat3 R = Mat3::Identity();  // rotation about world z
  Vec3 from = Vec3::Zero();   // p -> R (p - from) + to
  Vec3 to = Vec3::Zero();

  // The gauge change that takes pose `moved` back to the position and yaw of `reference`
  // (its tilt stays as it is: the rotation about z closest to R_reference R_moved^T).
  static GaugeTransform restoring(const Pose& reference, const Pose& moved);

  Vec3 point(const Vec3& p_W) const { return R * (p_W - from) + to; }
  Pose pose(const Pose& T_WB) const { return Pose(Mat3(R * T_WB.R()), point(T_WB.p)); }

  // Transforms the variables of `values` by their key letter (core/key.h): poses (x) and
  // landmarks (l) move, velocities (v) and external forces (f) rotate, biases (b) stay.
  void apply(Values* values) const;
};

}  // namespace hdvio
