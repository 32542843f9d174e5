#include "hdvio/backend/imo/displacement_source.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

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

DisplacementSource makeThrustModelSource(std::vector<ThrustSample> thrust, double step_s,
                                         const Vec3& sigma, const Vec3& gravity) {
  if (!(step_s > 0.0)) throw std::invalid_argument("makeThrustModelSource: step must be > 0");
  auto samples = std::make_shared<const std::vector<ThrustSample>>(std::move(thrust));
  const Mat3 cov = sigma.cwiseAbs2().asDiagonal();
  return [samples, step_s, cov, gravity](const DisplacementRequest& r)
             -> std::optional<DisplacementEstimate> {
    const double window = secondsBetween(r.t_begin, r.t_end);
    if (samples->empty() || r.t_begin < samples->front().t || r.t_end > samples->back().t)
      return std::nullopt;
    const int n = std::max(1, static_cast<int>(std::lround(window / step_s)));
    const double h = window / n;
    Vec3 u = Vec3::Zero();  // velocity change since t_begin
    Vec3 z = Vec3::Zero();
    for (int m = 0; m < n; ++m) {
      const Timestamp t_mid = r.t_begin + fromSeconds((m + 0.5) * h);
      const Vec3 a = r.world_from_body(t_mid) * *thrustAt(*samples, t_mid) + gravity;
      z += u * h + 0.5 * a * h * h;
      u += a * h;
    }
    return DisplacementEstimate{z + window * r.velocity_begin, cov, 0.0};
  };
}

}  // namespace hdvio::imo
