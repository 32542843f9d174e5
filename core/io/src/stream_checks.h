#pragma once
// Checks shared by the readers: time order, IMU gaps, unit quaternions.
#include <string>

#include "hdvio/core/error.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/time.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

// Enforces strictly increasing timestamps over one stream. A row that repeats the previous one
// exactly is dropped and counted (recorders sometimes log a sample twice); any other repeat or
// backwards step is an InputError.
class TimeOrder {
 public:
  TimeOrder(std::string file, std::string stream) : file_(std::move(file)), stream_(std::move(stream)) {}

  // Returns false if the row is an exact duplicate of the previous one and must be skipped.
  bool accept(Timestamp t, bool same_as_previous_row, long line);
  int duplicates() const { return duplicates_; }
  // "imu0: dropped 2 exactly duplicated rows (file)" or empty.
  std::string warning() const;

 private:
  std::string file_;
  std::string stream_;
  bool has_previous_ = false;
  Timestamp previous_ = 0;
  int duplicates_ = 0;
};

// Throws if t - previous exceeds max_gap_s (previous < 0 sample index means "none yet").
void checkImuGap(Timestamp previous, Timestamp t, double max_gap_s, const std::string& file,
                 long line);

// Validates a quaternion read from a file (|q| within 1e-2 of 1) and normalizes it, leaving
// quaternions that are already unit to machine precision untouched so that write/read round
// trips are bit-exact.
Quat unitQuaternion(double w, double x, double y, double z, const std::string& file, long line);

// With rotor speeds and a thrust coefficient or mass among the options: sets
// seq->rotor_calibration from its current value (sensor.yaml) overridden by the options, and
// throws naming `where` unless both end up positive.
void applyRotorOptions(const ReadOptions& options, const std::string& where, Sequence* seq);

// A Pose whose quaternion is taken as is (already unit), without renormalizing.
Pose poseExact(const Quat& q, const Vec3& p);

}  // namespace hdvio::io
