#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

void Trajectory::reserve(std::size_t n) {
  t.reserve(n);
  p.reserve(n);
  R.reserve(n);
}

void Trajectory::push(Timestamp time, const Vec3& position, const Mat3& rotation) {
  t.push_back(time);
  p.push_back(position);
  R.push_back(rotation);
}

Trajectory Trajectory::subset(const std::vector<std::size_t>& ids) const {
  Trajectory out;
  out.source = source;
  out.has_timestamps = has_timestamps;
  out.reserve(ids.size());
  for (std::size_t i : ids) {
    out.push(t[i], p[i], R[i]);
    if (hasVelocity()) out.v.push_back(v[i]);
  }
  return out;
}

Trajectory Trajectory::between(Timestamp begin, Timestamp end) const {
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= begin && t[i] <= end) ids.push_back(i);
  Trajectory out = subset(ids);
  for (std::size_t k = 1; k < out.t.size(); ++k) out.repeated_stamps += out.t[k] == out.t[k - 1];
  return out;
}

double Trajectory::pathLength() const {
  double length = 0.0;
  for (std::size_t i = 1; i < p.size(); ++i) length += (p[i] - p[i - 1]).norm();
  return length;
}

std::string repeatedStampsWarning(const Trajectory& traj) {
  if (traj.repeated_stamps == 0) return {};
  const std::size_t n = traj.repeated_stamps;
  return "warning: " + traj.source + ": " + std::to_string(n) + (n == 1 ? " pose repeats" : " poses repeat") +
         " the previous timestamp; all kept and associated one by one, as evo does";
}

}  // namespace hdvio::eval
