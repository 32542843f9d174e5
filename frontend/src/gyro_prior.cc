#include "hdvio/frontend/gyro_prior.h"

#include <algorithm>

namespace hdvio::frontend {

Quat integrateGyro(const std::vector<ImuSample>& imu, Timestamp t0, Timestamp t1,
                   const Vec3& gyro_bias) {
  Quat q = Quat::Identity();
  if (t1 <= t0 || imu.empty()) return q;
  // First sample at or before t0 (or the first one at all).
  auto it = std::upper_bound(imu.begin(), imu.end(), t0,
                             [](Timestamp t, const ImuSample& s) { return t < s.t; });
  if (it != imu.begin()) --it;
  for (; it != imu.end() && it->t < t1; ++it) {
    const Timestamp a = std::max(it->t, t0);
    const Timestamp b = (it + 1 == imu.end()) ? t1 : std::min((it + 1)->t, t1);
    if (b <= a) continue;
    q = q * quatExp((it->gyro - gyro_bias) * secondsBetween(a, b));
  }
  return q.normalized();
}

}  // namespace hdvio::frontend
