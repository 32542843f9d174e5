#include "stream_checks.h"

#include <cmath>
#include <cstdio>

namespace hdvio::io {

bool TimeOrder::accept(Timestamp t, bool same_as_previous_row, long line) {
  if (has_previous_) {
    if (t == previous_) {
      if (same_as_previous_row) {
        ++duplicates_;
        return false;
      }
      throw InputError(file_, line, "duplicate timestamp " + std::to_string(t) +
                                        " with different values");
    }
    if (t < previous_) {
      throw InputError(file_, line, "non-monotonic timestamp " + std::to_string(t) +
                                        " after " + std::to_string(previous_));
    }
  }
  has_previous_ = true;
  previous_ = t;
  return true;
}

std::string TimeOrder::warning() const {
  if (duplicates_ == 0) return {};
  return stream_ + ": dropped " + std::to_string(duplicates_) + " exactly duplicated row" +
         (duplicates_ == 1 ? "" : "s") + " (" + file_ + ")";
}

void checkImuGap(Timestamp previous, Timestamp t, double max_gap_s, const std::string& file,
                 long line) {
  // Stamps of opposite sign far apart overflow t - previous: that is a gap too long anyway.
  Timestamp span = 0;
  const double gap = __builtin_sub_overflow(t, previous, &span) ? HUGE_VAL : secondsBetween(previous, t);
  if (gap > max_gap_s) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "IMU gap of %.4f s before timestamp %lld exceeds max_imu_gap_s = %g s",
                  gap, static_cast<long long>(t), max_gap_s);
    throw InputError(file, line, buf);
  }
}

Quat unitQuaternion(double w, double x, double y, double z, const std::string& file, long line) {
  Quat q(w, x, y, z);
  const double n2 = q.squaredNorm();
  if (!(std::fabs(std::sqrt(n2) - 1.0) <= 1e-2)) {
    throw InputError(file, line, "quaternion norm " + std::to_string(std::sqrt(n2)) +
                                     " is not 1 (expected a unit quaternion)");
  }
  if (std::fabs(n2 - 1.0) > 1e-14) q.normalize();
  return q;
}

void applyRotorOptions(const ReadOptions& options, const std::string& where, Sequence* seq) {
  if (seq->rotor.empty() || !(options.thrust_coefficient || options.mass)) return;
  RotorCalibration c = seq->rotor_calibration.value_or(RotorCalibration{});
  if (options.thrust_coefficient) c.thrust_coefficient = *options.thrust_coefficient;
  if (options.mass) c.mass = *options.mass;
  if (!(c.thrust_coefficient > 0.0 && c.mass > 0.0))
    throw InputError(where, 0, "no sensor.yaml: both a positive thrust coefficient and mass are needed");
  seq->rotor_calibration = c;
}

Pose poseExact(const Quat& q, const Vec3& p) {
  Pose pose;
  pose.q = q;
  pose.p = p;
  return pose;
}

}  // namespace hdvio::io
