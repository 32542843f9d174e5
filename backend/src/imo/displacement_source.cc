#include "hdvio/backend/imo/displacement_source.h"

#include <algorithm>

namespace hdvio::imo {

std::optional<Vec3> thrustAt(const std::vector<ThrustSample>& thrust, Timestamp t) {
  if (thrust.empty() || t < thrust.front().t || t > thrust.back().t) return std::nullopt;
  auto hi = std::lower_bound(thrust.begin(), thrust.end(), t,
                             [](const ThrustSample& s, Timestamp tt) { return s.t < tt; });
  if (hi->t == t || hi == thrust.begin()) return hi->thrust;
  const auto lo = std::prev(hi);
  const double a = secondsBetween(lo->t, t) / secondsBetween(lo->t, hi->t);
  return ((1.0 - a) * lo->thrust + a * hi->thrust).eval();
}

}  // namespace hdvio::imo
