#include "hdvio/core/sequence.h"

#include <algorithm>
#include <iterator>

#include "hdvio/core/error.h"

namespace hdvio {

NavState groundTruthState(const Sequence& seq, Timestamp t) {
  const auto& gt = seq.groundtruth;
  if (gt.empty() || t < gt.front().t || t > gt.back().t)
    throw InputError(seq.source, 0, "no ground truth at the first frame time");
  auto hi = std::lower_bound(gt.begin(), gt.end(), t,
                             [](const GroundTruthState& s, Timestamp tt) { return s.t < tt; });
  auto lo = hi == gt.begin() ? hi : std::prev(hi);
  const double a = hi->t == lo->t ? 0.0 : secondsBetween(lo->t, t) / secondsBetween(lo->t, hi->t);
  NavState s;
  s.t = t;
  s.T_WB = Pose(lo->T_WB.q.slerp(a, hi->T_WB.q), (1 - a) * lo->T_WB.p + a * hi->T_WB.p);
  s.v_W = (1 - a) * lo->v_W + a * hi->v_W;
  if (lo->has_biases) s.bias << lo->gyro_bias, lo->accel_bias;
  return s;
}

}  // namespace hdvio
