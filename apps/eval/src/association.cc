#include "hdvio/eval/association.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "hdvio/core/error.h"

namespace hdvio::eval {

AssociationMode parseAssociationMode(const std::string& name) {
  if (name == "timestamp") return AssociationMode::kTimestamp;
  if (name == "interpolate") return AssociationMode::kInterpolate;
  if (name == "index") return AssociationMode::kIndex;
  throw InputError("", 0, "unknown association '" + name + "' (timestamp|interpolate|index)");
}

std::string associationName(AssociationMode mode) {
  switch (mode) {
    case AssociationMode::kTimestamp: return "timestamp";
    case AssociationMode::kInterpolate: return "interpolate";
    case AssociationMode::kIndex: return "index";
  }
  return "?";
}

bool nearestIndex(const std::vector<Timestamp>& stamps, Timestamp t, Timestamp max_diff_ns,
                  std::size_t* index) {
  if (stamps.empty()) return false;
  const auto it = std::lower_bound(stamps.begin(), stamps.end(), t);
  std::size_t best = static_cast<std::size_t>(it - stamps.begin());
  if (best == stamps.size()) {
    best = stamps.size() - 1;
  } else if (best > 0 && std::llabs(stamps[best - 1] - t) <= std::llabs(stamps[best] - t)) {
    best = best - 1;  // np.argmin returns the first of equal distances
  }
  while (best > 0 && stamps[best - 1] == stamps[best]) --best;  // ... also of a repeated stamp
  if (std::llabs(stamps[best] - t) > max_diff_ns) return false;
  *index = best;
  return true;
}

void matchNearestStamps(const std::vector<Timestamp>& a, const std::vector<Timestamp>& b,
                        Timestamp max_diff_ns, std::vector<std::size_t>* ids_a,
                        std::vector<std::size_t>* ids_b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::size_t j = 0;
    if (nearestIndex(b, a[i], max_diff_ns, &j)) {
      ids_a->push_back(i);
      ids_b->push_back(j);
    }
  }
}

namespace {

Trajectory shifted(const Trajectory& traj, Timestamp offset) {
  Trajectory out = traj;
  for (Timestamp& t : out.t) t += offset;
  return out;
}

AssociatedPair byTimestamp(const Trajectory& ref, const Trajectory& est, Timestamp max_diff) {
  // evo matches the shorter trajectory's stamps against the longer one's.
  const bool est_longer = est.size() > ref.size();
  const Trajectory& shorter = est_longer ? ref : est;
  const Trajectory& longer = est_longer ? est : ref;
  std::vector<std::size_t> ids_short, ids_long;
  matchNearestStamps(shorter.t, longer.t, max_diff, &ids_short, &ids_long);
  AssociatedPair pair;
  pair.ref = est_longer ? ref.subset(ids_short) : ref.subset(ids_long);
  pair.est = est_longer ? est.subset(ids_long) : est.subset(ids_short);
  return pair;
}

AssociatedPair byInterpolation(const Trajectory& ref, const Trajectory& est, Timestamp max_diff) {
  AssociatedPair pair;
  pair.ref.source = ref.source;
  pair.ref.has_timestamps = true;
  std::vector<std::size_t> est_ids;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const Timestamp t = est.t[i];
    std::size_t nearest = 0;
    // The tolerance still applies: interpolation must not bridge gaps in the ground truth.
    if (!nearestIndex(ref.t, t, max_diff, &nearest)) continue;
    if (t < ref.t.front() || t > ref.t.back()) continue;
    const auto it = std::upper_bound(ref.t.begin(), ref.t.end(), t);
    const std::size_t hi = std::min<std::size_t>(it - ref.t.begin(), ref.size() - 1);
    const std::size_t lo = hi == 0 ? 0 : hi - 1;
    const double span = static_cast<double>(ref.t[hi] - ref.t[lo]);
    const double a = span > 0 ? static_cast<double>(t - ref.t[lo]) / span : 0.0;
    const Quat q_lo(ref.R[lo]), q_hi(ref.R[hi]);
    pair.ref.push(t, (1 - a) * ref.p[lo] + a * ref.p[hi],
                  q_lo.slerp(a, q_hi).normalized().toRotationMatrix());
    if (ref.hasVelocity()) pair.ref.v.push_back((1 - a) * ref.v[lo] + a * ref.v[hi]);
    est_ids.push_back(i);
  }
  pair.est = est.subset(est_ids);
  return pair;
}

}  // namespace

AssociatedPair associate(const Trajectory& ref, const Trajectory& est,
                         const AssociationOptions& options) {
  AssociatedPair pair;
  if (options.mode == AssociationMode::kIndex) {
    if (ref.size() != est.size())
      throw InputError(est.source, 0,
                       "index association needs equal lengths: ground truth has " +
                           std::to_string(ref.size()) + " poses, estimate " +
                           std::to_string(est.size()));
    pair.ref = ref;
    pair.est = est;
    return pair;
  }
  if (!ref.has_timestamps || !est.has_timestamps)
    throw InputError(ref.has_timestamps ? est.source : ref.source, 0,
                     "file has no timestamps (KITTI): use index association");
  const Timestamp max_diff = fromSeconds(options.max_time_diff_s);
  const Trajectory est_shifted = shifted(est, fromSeconds(options.time_offset_s));
  pair = options.mode == AssociationMode::kInterpolate ? byInterpolation(ref, est_shifted, max_diff)
                                                       : byTimestamp(ref, est_shifted, max_diff);
  if (pair.est.size() == 0)
    throw InputError(est.source, 0,
                     "no pose matches the ground truth within " +
                         std::to_string(options.max_time_diff_s) + " s (check the time unit/offset)");
  return pair;
}

}  // namespace hdvio::eval
