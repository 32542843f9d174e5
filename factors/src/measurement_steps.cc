#include "hdvio/factors/measurement_steps.h"

#include <algorithm>
#include <string>

#include "hdvio/core/error.h"

namespace hdvio {
namespace {

// Index range of samples used for [t_i, t_j]: the last sample at or before t_i up to the first
// at or after t_j. Validates coverage, ordering and finiteness inside that range.
template <class Sample, class Finite>
std::pair<std::size_t, std::size_t> coveringRange(const std::vector<Sample>& s, Timestamp t_i,
                                                  Timestamp t_j, const char* what,
                                                  Finite finite) {
  if (t_j <= t_i) throw InputError("", 0, std::string(what) + ": interval end is not after its start");
  if (s.empty() || s.front().t > t_i || s.back().t < t_j)
    throw InputError("", 0, std::string(what) + " samples do not cover the interval [" +
                                std::to_string(t_i) + ", " + std::to_string(t_j) + "] ns");
  auto after_i = std::upper_bound(s.begin(), s.end(), t_i,
                                  [](Timestamp t, const Sample& x) { return t < x.t; });
  const std::size_t first = static_cast<std::size_t>(after_i - s.begin()) - 1;
  auto at_j = std::lower_bound(s.begin(), s.end(), t_j,
                               [](const Sample& x, Timestamp t) { return x.t < t; });
  const std::size_t last = static_cast<std::size_t>(at_j - s.begin());
  for (std::size_t k = first; k <= last; ++k) {
    if (!finite(s[k])) throw InputError("", 0, std::string(what) + " sample at " +
                                                   std::to_string(s[k].t) + " ns is not finite");
    if (k > first && s[k].t <= s[k - 1].t)
      throw InputError("", 0, std::string(what) + " timestamps are not strictly increasing at " +
                                  std::to_string(s[k].t) + " ns");
  }
  return {first, last};
}

// Linear interpolation of member `field` at time t, searching forward from *cursor.
template <class Sample>
Vec3 interpolate(const std::vector<Sample>& s, std::size_t last, Timestamp t, std::size_t* cursor,
                 Vec3 Sample::*field) {
  while (*cursor + 1 < last && s[*cursor + 1].t <= t) ++*cursor;
  const Sample& a = s[*cursor];
  const Sample& b = s[std::min(*cursor + 1, last)];
  if (b.t == a.t) return a.*field;
  const double w = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return (1.0 - w) * (a.*field) + w * (b.*field);
}

bool finiteImu(const ImuSample& x) { return x.gyro.allFinite() && x.accel.allFinite(); }
bool finiteThrust(const ThrustSample& x) { return x.thrust.allFinite(); }

// All step boundaries: t_i, every sample time strictly inside, t_j.
std::vector<Timestamp> boundaries(Timestamp t_i, Timestamp t_j,
                                  const std::vector<Timestamp>& inner) {
  std::vector<Timestamp> t;
  t.reserve(inner.size() + 2);
  t.push_back(t_i);
  t.insert(t.end(), inner.begin(), inner.end());
  t.push_back(t_j);
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

template <class Sample>
void appendInner(const std::vector<Sample>& s, std::size_t first, std::size_t last, Timestamp t_i,
                 Timestamp t_j, std::vector<Timestamp>* out) {
  for (std::size_t k = first; k <= last; ++k)
    if (s[k].t > t_i && s[k].t < t_j) out->push_back(s[k].t);
}

}  // namespace

std::vector<ImuStep> imuSteps(const std::vector<ImuSample>& imu, Timestamp t_i, Timestamp t_j) {
  const auto [first, last] = coveringRange(imu, t_i, t_j, "IMU", finiteImu);
  std::vector<Timestamp> inner;
  appendInner(imu, first, last, t_i, t_j, &inner);
  const std::vector<Timestamp> t = boundaries(t_i, t_j, inner);
  std::vector<ImuStep> steps(t.size() - 1);
  std::size_t cg = first, ca = first;
  Vec3 g0 = interpolate(imu, last, t[0], &cg, &ImuSample::gyro);
  Vec3 a0 = interpolate(imu, last, t[0], &ca, &ImuSample::accel);
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    const Vec3 g1 = interpolate(imu, last, t[k + 1], &cg, &ImuSample::gyro);
    const Vec3 a1 = interpolate(imu, last, t[k + 1], &ca, &ImuSample::accel);
    steps[k].dt = secondsBetween(t[k], t[k + 1]);
    steps[k].gyro = 0.5 * (g0 + g1);
    steps[k].accel = 0.5 * (a0 + a1);
    g0 = g1;
    a0 = a1;
  }
  return steps;
}

std::vector<DynamicsStep> dynamicsSteps(const std::vector<ImuSample>& imu,
                                        const std::vector<ThrustSample>& thrust, Timestamp t_i,
                                        Timestamp t_j, const ResidualForceFn& residual_force) {
  const auto [fi, li] = coveringRange(imu, t_i, t_j, "IMU", finiteImu);
  const auto [ft, lt] = coveringRange(thrust, t_i, t_j, "thrust", finiteThrust);
  std::vector<Timestamp> inner;
  appendInner(imu, fi, li, t_i, t_j, &inner);
  appendInner(thrust, ft, lt, t_i, t_j, &inner);
  const std::vector<Timestamp> t = boundaries(t_i, t_j, inner);

  struct Point { Vec3 gyro, accel, thrust, res; };
  std::size_t cg = fi, ca = fi, ct = ft;
  auto at = [&](Timestamp time) {
    Point p;
    p.gyro = interpolate(imu, li, time, &cg, &ImuSample::gyro);
    p.accel = interpolate(imu, li, time, &ca, &ImuSample::accel);
    p.thrust = interpolate(thrust, lt, time, &ct, &ThrustSample::thrust);
    p.res = residual_force ? residual_force(time) : Vec3::Zero();
    if (!p.res.allFinite())
      throw InputError("", 0, "residual force at " + std::to_string(time) + " ns is not finite");
    return p;
  };
  std::vector<DynamicsStep> steps(t.size() - 1);
  Point p0 = at(t[0]);
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    const Point p1 = at(t[k + 1]);
    steps[k].dt = secondsBetween(t[k], t[k + 1]);
    steps[k].gyro = 0.5 * (p0.gyro + p1.gyro);
    steps[k].accel = 0.5 * (p0.accel + p1.accel);
    steps[k].thrust = 0.5 * (p0.thrust + p1.thrust);
    steps[k].residual_force = 0.5 * (p0.res + p1.res);
    p0 = p1;
  }
  return steps;
}

}  // namespace hdvio
