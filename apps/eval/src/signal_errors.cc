#include "hdvio/eval/signal_errors.h"

#include <cmath>

#include "hdvio/eval/association.h"

namespace hdvio::eval {

VectorErrors vectorErrors(const std::vector<Timestamp>& t, const std::vector<Vec3>& estimate,
                          const std::vector<Vec3>& truth) {
  VectorErrors e;
  e.t = t;
  e.estimate = estimate;
  e.truth = truth;
  std::vector<double> total, xy, z;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const Vec3 d = estimate[i] - truth[i];
    total.push_back(d.norm());
    xy.push_back(d.head<2>().norm());
    z.push_back(std::fabs(d.z()));
  }
  e.total = computeStatistics(total);
  e.xy = computeStatistics(xy);
  e.z = computeStatistics(z);
  return e;
}

std::optional<VectorErrors> velocityErrors(const Trajectory& gt, const VectorSeries& est,
                                           const SimilarityTransform& alignment,
                                           Timestamp max_diff_ns) {
  if (!gt.hasVelocity()) return std::nullopt;
  std::vector<Timestamp> t;
  std::vector<Vec3> e, g;
  for (std::size_t i = 0; i < est.size(); ++i) {
    std::size_t j = 0;
    if (!nearestIndex(gt.t, est.t[i], max_diff_ns, &j)) continue;
    t.push_back(est.t[i]);
    e.push_back(alignment.s * (alignment.R * est.value[i]));
    g.push_back(gt.v[j]);
  }
  if (t.empty()) return std::nullopt;
  return vectorErrors(t, e, g);
}

std::optional<ForceErrors> forceErrors(const ForceGroundTruth& gt, const VectorSeries& est,
                                       Timestamp max_diff_ns) {
  std::vector<Timestamp> t;
  std::vector<Vec3> e, ext, total;
  for (std::size_t i = 0; i < est.size(); ++i) {
    std::size_t j = 0;
    if (!nearestIndex(gt.t, est.t[i], max_diff_ns, &j)) continue;
    t.push_back(est.t[i]);
    e.push_back(est.value[i]);
    ext.push_back(gt.external[j]);
    total.push_back(gt.external[j] + gt.drag[j]);
  }
  if (t.empty()) return std::nullopt;
  return ForceErrors{vectorErrors(t, e, ext), vectorErrors(t, e, total)};
}

}  // namespace hdvio::eval
