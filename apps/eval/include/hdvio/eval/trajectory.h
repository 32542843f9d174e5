#pragma once
// In-memory trajectories as the evaluation reads them. Rotations are stored as matrices, exactly
// as read: KITTI files carry slightly non-orthonormal matrices and evo uses them unchanged, so
// re-orthonormalizing here would move the reproduced numbers away from evo's.
#include <string>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio::eval {

struct Trajectory {
  std::string source;           // file it was read from, for messages
  bool has_timestamps = true;   // false for KITTI pose files (poses correspond by index)
  std::vector<Timestamp> t;     // ns; for KITTI files the index times 1 s
  std::vector<Vec3> p;          // position in the world frame, m
  std::vector<Mat3> R;          // orientation of the body in the world
  std::vector<Vec3> v;          // world-frame velocity, m/s: empty or one per pose
  // Poses whose stamp equals the previous pose's. They are kept and associated one by one, as
  // evo does; repeatedStampsWarning() says so.
  std::size_t repeated_stamps = 0;

  std::size_t size() const { return p.size(); }
  bool hasVelocity() const { return !v.empty() && v.size() == p.size(); }
  void reserve(std::size_t n);
  void push(Timestamp time, const Vec3& position, const Mat3& rotation);
  Trajectory subset(const std::vector<std::size_t>& ids) const;
  // The poses stamped in [begin, end].
  Trajectory between(Timestamp begin, Timestamp end) const;
  // Length of the polyline through all positions, m.
  double pathLength() const;
};

// "warning: <source>: 4 poses repeat the previous timestamp; all kept, as evo does" or empty.
std::string repeatedStampsWarning(const Trajectory& traj);

// A timestamped 3-vector signal: estimated velocity or force.
struct VectorSeries {
  std::string source;
  std::vector<Timestamp> t;
  std::vector<Vec3> value;
  std::size_t size() const { return t.size(); }
};

// force_groundtruth0: mass-normalized forces in the IMU frame (m/s^2).
struct ForceGroundTruth {
  std::string source;
  std::vector<Timestamp> t;
  std::vector<Vec3> external;
  std::vector<Vec3> drag;
  std::size_t size() const { return t.size(); }
};

}  // namespace hdvio::eval
