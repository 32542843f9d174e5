#include "hdvio/backend/imo/imo_run_support.h"

#include <algorithm>
#include <iterator>

namespace hdvio::imo {

ImoNominalState nominalFrom(const NavState& s) {
  ImoNominalState x;
  x.t = s.t;
  x.R = s.T_WB.R();
  x.p = s.T_WB.p;
  x.v = s.v_W;
  x.bg = s.bias.head<3>();
  x.ba = s.bias.tail<3>();
  return x;
}

NavState navFrom(const ImoNominalState& x) {
  NavState s;
  s.t = x.t;
  s.T_WB = Pose(x.R, x.p);
  s.v_W = x.v;
  s.bias << x.bg, x.ba;
  return s;
}

ImuSample interpolateImu(const ImuSample& a, const ImuSample& b, Timestamp t) {
  const double s = secondsBetween(a.t, t) / secondsBetween(a.t, b.t);
  return {t, (1.0 - s) * a.gyro + s * b.gyro, (1.0 - s) * a.accel + s * b.accel};
}

void RotationHistory::add(Timestamp t, const Quat& q) {
  if (!entries_.empty() && entries_.back().first == t) entries_.back().second = q;
  else entries_.emplace_back(t, q);
}

Quat RotationHistory::at(Timestamp t) const {
  if (t <= entries_.front().first) return entries_.front().second;
  if (t >= entries_.back().first) return entries_.back().second;
  auto hi = std::lower_bound(entries_.begin(), entries_.end(), t,
                             [](const auto& e, Timestamp tt) { return e.first < tt; });
  if (hi->first == t) return hi->second;
  const auto lo = std::prev(hi);
  const double a = secondsBetween(lo->first, t) / secondsBetween(lo->first, hi->first);
  return lo->second.slerp(a, hi->second);
}

void RotationHistory::dropBefore(Timestamp t) {
  while (entries_.size() > 1 && entries_[1].first <= t) entries_.pop_front();
}

DisplacementRequest windowRequest(const ImoFilter& filter, const RotationHistory& history,
                                  int clone_i, Timestamp t_begin, Timestamp t_end) {
  const ImoClone& begin = filter.clones().at(static_cast<std::size_t>(clone_i));
  DisplacementRequest request;
  request.t_begin = t_begin;
  request.t_end = t_end;
  const Quat anchor = Quat(begin.R) * history.at(t_begin).conjugate();
  request.world_from_body = [&history, anchor](Timestamp t) { return anchor * history.at(t); };
  request.gyro_bias = filter.state().bg;
  request.accel_bias = filter.state().ba;
  request.velocity_begin = begin.v;
  return request;
}

RelativePositionMeasurement displacementMeasurement(const DisplacementEstimate& est, int clone_i,
                                                    int clone_j, const Mat3& covariance) {
  RelativePositionMeasurement m;
  m.clone_i = clone_i;
  m.clone_j = clone_j;
  m.z = est.z;
  m.covariance = covariance;
  m.velocity_coefficient = est.velocity_coefficient;
  m.velocity_matrix = est.velocity_matrix;
  m.attitude_jacobian = est.attitude_jacobian;
  return m;
}

}  // namespace hdvio::imo
