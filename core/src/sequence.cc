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

namespace {
// Drops the samples after `end`; the streams are sorted by time (the readers check it).
template <typename Sample>
void cutAfter(std::vector<Sample>* samples, Timestamp end) {
  samples->erase(std::upper_bound(samples->begin(), samples->end(), end,
                                  [](Timestamp tt, const Sample& s) { return tt < s.t; }),
                 samples->end());
}
}  // namespace

Sequence sequenceUntil(const Sequence& seq, Timestamp end) {
  Sequence cut = seq;
  cutAfter(&cut.imu, end);
  cutAfter(&cut.thrust, end);
  cutAfter(&cut.rotor, end);
  cutAfter(&cut.images, end);
  cutAfter(&cut.groundtruth, end);
  cutAfter(&cut.forces, end);
  cutAfter(&cut.landmark_observations, end);
  return cut;
}

}  // namespace hdvio
