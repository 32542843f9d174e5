#include "hdvio/eval/pose_errors.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hdvio/core/error.h"

namespace hdvio::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

Mat4 homogeneous(const Mat3& R, const Vec3& p) {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = p;
  return T;
}

// evo's lie.se3_inverse: uses the transpose, not a general inverse, also for KITTI matrices.
Mat4 se3Inverse(const Mat4& T) {
  Mat4 inv = Mat4::Identity();
  const Mat3 Rt = T.topLeftCorner<3, 3>().transpose();
  inv.topLeftCorner<3, 3>() = Rt;
  inv.topRightCorner<3, 1>() = -Rt * T.topRightCorner<3, 1>();
  return inv;
}

Mat4 relativeSe3(const Mat4& a, const Mat4& b) { return se3Inverse(a) * b; }

// Cumulative travelled distance, 0 at the first pose (rpg get_distance_from_start).
std::vector<double> distancesFromStart(const std::vector<Vec3>& p) {
  std::vector<double> d(p.size(), 0.0);
  for (std::size_t i = 1; i < p.size(); ++i) d[i] = d[i - 1] + (p[i] - p[i - 1]).norm();
  return d;
}

// evo's bounded_binary_search over arc lengths from pose i, returning (found, j).
// `cumulative` holds the path length from pose 0, so arc(i, x) is a difference of two entries.
bool boundedBinarySearch(const std::vector<double>& cumulative, std::size_t i, double target,
                         double lower, double upper, std::size_t* result) {
  const long length = static_cast<long>(cumulative.size());
  // geometry.arc_len(positions[i:x+1]); Python slicing makes it 0 for x < i and clips at the end.
  auto arc = [&](long x) {
    if (x < static_cast<long>(i)) return 0.0;
    return cumulative[std::min(x, length - 1)] - cumulative[i];
  };
  long start = 0, end = length - 1, mid = -1;
  bool found = false;
  while (start <= end && !found) {
    mid = (start + end) / 2;
    const double val = arc(mid);
    if (lower <= val && val <= upper) {
      const double residual = std::fabs(val - target);
      if (std::fabs(arc(mid - 1) - target) <= residual) {
        end = mid - 1;
        continue;
      } else if (std::fabs(arc(mid + 1) - target) < residual) {
        start = mid + 1;
        continue;
      } else {
        found = true;
      }
    }
    if (!found) {
      if (target < val) end = mid - 1;
      else start = mid + 1;
    }
  }
  *result = static_cast<std::size_t>(mid);
  return found;
}

}  // namespace

double rotationAngleDeg(const Mat3& R) {
  // atan2 of sin and cos parts: as acos((tr R - 1) / 2) but accurate for tiny angles too.
  const double c = (R.trace() - 1.0) / 2.0;
  const double s = 0.5 * Vec3(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)).norm();
  return std::atan2(s, c) * kRadToDeg;
}

AbsoluteErrors absoluteErrors(const Trajectory& ref, const Trajectory& est_aligned) {
  AbsoluteErrors e;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    e.translation.push_back((est_aligned.p[i] - ref.p[i]).norm());
    e.rotation_deg.push_back(rotationAngleDeg(est_aligned.R[i].transpose() * ref.R[i]));
  }
  return e;
}

DeltaUnit parseDeltaUnit(const std::string& name) {
  if (name == "f") return DeltaUnit::kFrames;
  if (name == "m") return DeltaUnit::kMeters;
  throw InputError("", 0, "unknown RPE delta unit '" + name + "' (f|m)");
}

IndexPairs evoPairs(const std::vector<Vec3>& positions, const EvoRpeOptions& options) {
  IndexPairs pairs;
  const std::size_t n = positions.size();
  if (options.delta <= 0) throw InputError("", 0, "RPE delta must be positive");
  if (options.unit == DeltaUnit::kFrames) {
    const std::size_t delta = static_cast<std::size_t>(options.delta);
    if (static_cast<double>(delta) != options.delta)
      throw InputError("", 0, "RPE delta in frames must be an integer");
    if (options.all_pairs) {
      for (std::size_t i = 0; i + delta < n; ++i) pairs.emplace_back(i, i + delta);
    } else {
      for (std::size_t i = 0; i + delta < n; i += delta) pairs.emplace_back(i, i + delta);
    }
  } else if (options.all_pairs) {
    const double tol = options.delta * options.rel_delta_tol;
    const std::vector<double> cumulative = distancesFromStart(positions);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t j = 0;
      if (boundedBinarySearch(cumulative, i, options.delta, options.delta - tol,
                              options.delta + tol, &j))
        pairs.emplace_back(i, j);
    }
  } else {
    // filter_pairs_by_path: a new id every time the path since the last id reaches delta.
    std::vector<std::size_t> ids;
    double path = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      path += (positions[i] - positions[i == 0 ? 0 : i - 1]).norm();
      if (path >= options.delta) {
        ids.push_back(i);
        path = 0.0;
      }
    }
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) pairs.emplace_back(ids[k], ids[k + 1]);
  }
  return pairs;
}

RelativeErrors evoRelativeErrors(const Trajectory& ref, const Trajectory& est,
                                 const EvoRpeOptions& options) {
  RelativeErrors r;
  r.pairs = evoPairs(options.pairs_from_reference ? ref.p : est.p, options);
  for (const auto& [i, j] : r.pairs) {
    const Mat4 Q_rel = relativeSe3(homogeneous(ref.R[i], ref.p[i]), homogeneous(ref.R[j], ref.p[j]));
    const Mat4 P_rel = relativeSe3(homogeneous(est.R[i], est.p[i]), homogeneous(est.R[j], est.p[j]));
    const Mat4 E = relativeSe3(Q_rel, P_rel);
    r.translation.push_back(E.topRightCorner<3, 1>().norm());
    r.rotation_deg.push_back(rotationAngleDeg(E.topLeftCorner<3, 3>()));
  }
  return r;
}

RpgRelativeError rpgRelativeError(const Trajectory& ref, const Trajectory& est, double distance,
                                  double max_dist_diff, double scale) {
  RpgRelativeError r;
  r.distance = distance;
  if (max_dist_diff <= 0) max_dist_diff = 0.2 * distance;
  const std::vector<double> d = distancesFromStart(ref.p);
  // compute_comparison_indices_length: for each start, the end whose path distance is closest
  // to start + distance, if closer than max_dist_diff.
  std::vector<std::size_t> comparisons;
  for (std::size_t idx = 0; idx < d.size(); ++idx) {
    long best = -1;
    double error = max_dist_diff;
    const double target = d[idx] + distance;
    for (std::size_t i = idx; i < d.size(); ++i) {
      if (std::fabs(d[i] - target) < error) {
        best = static_cast<long>(i);
        error = std::fabs(d[i] - target);
      }
      if (d[i] > target + max_dist_diff) break;  // monotone: nothing closer further on
    }
    if (best != -1) comparisons.push_back(static_cast<std::size_t>(best));
  }
  if (comparisons.size() < 2) return r;  // "Too few samples! Will not compute."
  // The toolbox pairs the k-th found end with start index k; kept for identical numbers.
  for (std::size_t idx = 0; idx < comparisons.size(); ++idx) {
    const std::size_t c = comparisons[idx];
    const Mat3 R_c1 = est.R[idx], R_c2 = est.R[c];
    const Vec3 t_c1_c2 = scale * (R_c1.transpose() * (est.p[c] - est.p[idx]));
    const Mat3 R_c1_c2 = R_c1.transpose() * R_c2;
    const Mat3 R_m1_m2 = ref.R[idx].transpose() * ref.R[c];
    const Vec3 t_m1_m2 = ref.R[idx].transpose() * (ref.p[c] - ref.p[idx]);
    // T_error_in_c2 = inv(T_m1_m2) * T_c1_c2, expressed in the world by R_c2.
    const Mat3 R_err_c2 = R_m1_m2.transpose() * R_c1_c2;
    const Vec3 t_err_c2 = R_m1_m2.transpose() * (t_c1_c2 - t_m1_m2);
    const Mat3 R_err = R_c2 * R_err_c2 * R_c2.transpose();
    const Vec3 t_err = R_c2 * t_err_c2;
    const double tn = t_err.norm();
    r.start_ids.push_back(idx);
    r.translation.push_back(tn);
    r.translation_percent.push_back(tn / distance * 100.0);
    r.rotation_deg.push_back(rotationAngleDeg(R_err));
    // euler_from_matrix(e, 'rzyx') -> (yaw, pitch, roll) with R = Rz Ry Rx.
    const double cy = std::sqrt(R_err(0, 0) * R_err(0, 0) + R_err(1, 0) * R_err(1, 0));
    double yaw, pitch, roll;
    if (cy > 4.0 * std::numeric_limits<double>::epsilon()) {
      yaw = std::atan2(R_err(1, 0), R_err(0, 0));
      pitch = std::atan2(-R_err(2, 0), cy);
      roll = std::atan2(R_err(2, 1), R_err(2, 2));
    } else {
      yaw = 0.0;
      pitch = std::atan2(-R_err(2, 0), cy);
      roll = std::atan2(-R_err(1, 2), R_err(1, 1));
    }
    r.yaw_deg.push_back(std::fabs(yaw) * kRadToDeg);
    r.gravity_deg.push_back(std::sqrt(pitch * pitch + roll * roll) * kRadToDeg);
  }
  return r;
}

std::vector<double> rpgDistancesFromFractions(double trajectory_length,
                                              const std::vector<double>& fractions) {
  std::vector<double> out;
  for (double f : fractions) out.push_back(std::trunc(f * trajectory_length * 100.0) / 100.0);
  return out;
}

}  // namespace hdvio::eval
