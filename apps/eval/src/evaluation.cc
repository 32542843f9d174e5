#include "hdvio/eval/evaluation.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>

namespace hdvio::eval {

std::vector<double> relativeErrorDistances(const GroundTruth& gt, const EvaluationOptions& options) {
  std::vector<double> d = options.rpe_distances_m;
  const std::vector<double> from_fractions =
      rpgDistancesFromFractions(gt.trajectory.pathLength(), options.rpe_fractions);
  d.insert(d.end(), from_fractions.begin(), from_fractions.end());
  d.erase(std::remove_if(d.begin(), d.end(), [](double x) { return !(x > 0.0); }), d.end());
  std::sort(d.begin(), d.end());
  d.erase(std::unique(d.begin(), d.end()), d.end());
  return d;
}

namespace {

// An alignment that fits the yaw to the positions cannot find it when the trajectory's horizontal
// extent is small against the position error (hovering, small flights): ATE_R then measures the
// fitted yaw, not the estimate's attitude. Says so, with the numbers.
std::optional<std::string> yawAlignmentNote(AlignmentType alignment, const Trajectory& ref,
                                            double ate_rmse) {
  if (alignment == AlignmentType::kNone || ref.p.size() < 2 || !std::isfinite(ate_rmse))
    return std::nullopt;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Vec3& p : ref.p) mean += p.head<2>();
  mean /= static_cast<double>(ref.p.size());
  double sq = 0.0;
  for (const Vec3& p : ref.p) sq += (p.head<2>() - mean).squaredNorm();
  const double extent = std::sqrt(sq / static_cast<double>(ref.p.size()));  // RMS radius, m
  if (extent >= 3.0 * ate_rmse) return std::nullopt;
  std::ostringstream note;
  note << std::setprecision(3) << "ATE_R: the horizontal extent of the trajectory (RMS radius "
       << extent << " m) is under 3x the position error (" << ate_rmse
       << " m), so the yaw the " << alignmentName(alignment)
       << " alignment fits, and with it ATE_R, is ill-determined; compare with --align none";
  return note.str();
}

}  // namespace

EstimateResult evaluateEstimate(const GroundTruth& gt, const Estimate& est,
                                const EvaluationOptions& options,
                                const std::vector<double>& distances) {
  EstimateResult r;
  r.name = est.name;
  r.source = est.trajectory.source;
  r.num_poses = est.trajectory.size();
  const AssociatedPair pair = associate(gt.trajectory, est.trajectory, options.association);
  r.num_matched = pair.est.size();
  r.ref_matched = pair.ref;
  r.alignment = computeAlignment(options.alignment, pair.ref, pair.est, options.align_first_n);
  r.est_aligned = applyAlignment(r.alignment, pair.est);

  r.ate = absoluteErrors(pair.ref, r.est_aligned);
  r.ate_translation = computeStatistics(r.ate.translation);
  r.ate_rotation_deg = computeStatistics(r.ate.rotation_deg);
  if (const std::optional<std::string> note = yawAlignmentNote(options.alignment, pair.ref,
                                                                r.ate_translation.rmse))
    r.notes.push_back(*note);

  if (options.evo_rpe) {
    // Relative errors do not depend on a rigid alignment; with Sim(3) they see the scale.
    RelativeErrors rpe = evoRelativeErrors(pair.ref, r.est_aligned, options.evo_rpe_options);
    if (rpe.pairs.empty()) {
      r.notes.push_back("evo RPE: delta too large for this trajectory, no pairs");
    } else {
      r.evo_rpe_translation = computeStatistics(rpe.translation);
      r.evo_rpe_rotation_deg = computeStatistics(rpe.rotation_deg);
      r.evo_rpe = std::move(rpe);
    }
  }

  const double scale = options.alignment == AlignmentType::kSim3 ? r.alignment.s : 1.0;
  for (double d : distances) {
    RelativeErrorSummary s;
    s.distance = d;
    s.errors = rpgRelativeError(pair.ref, pair.est, d, -1.0, scale);
    if (s.errors.translation.empty()) {
      std::ostringstream note;
      note << "relative error at " << d << " m: too few sub-trajectories";
      r.notes.push_back(note.str());
    }
    s.translation = computeStatistics(s.errors.translation);
    s.translation_percent = computeStatistics(s.errors.translation_percent);
    s.rotation_deg = computeStatistics(s.errors.rotation_deg);
    s.yaw_deg = computeStatistics(s.errors.yaw_deg);
    r.relative.push_back(std::move(s));
  }

  const Timestamp max_diff = fromSeconds(options.association.max_time_diff_s);
  const bool timed = est.trajectory.has_timestamps && gt.trajectory.has_timestamps;
  std::optional<VectorSeries> velocity = est.velocity;
  if (!velocity && est.trajectory.hasVelocity()) {
    velocity = VectorSeries{est.trajectory.source, est.trajectory.t, est.trajectory.v};
  }
  if (velocity && timed) {
    VectorSeries shifted = *velocity;
    for (Timestamp& t : shifted.t) t += fromSeconds(options.association.time_offset_s);
    r.velocity = velocityErrors(gt.trajectory, shifted, r.alignment, max_diff);
    if (!r.velocity) r.notes.push_back("velocity: no ground-truth velocity at the estimate's stamps");
  }
  if (est.force) {
    if (!gt.forces) {
      r.notes.push_back("force: the ground truth has no force_groundtruth0");
    } else {
      VectorSeries shifted = *est.force;
      for (Timestamp& t : shifted.t) t += fromSeconds(options.association.time_offset_s);
      r.force = forceErrors(*gt.forces, shifted, max_diff);
      if (!r.force) r.notes.push_back("force: no ground-truth force at the estimate's stamps");
      if (r.force && est.total_force) {
        VectorSeries total = *est.total_force;
        for (Timestamp& t : total.t) t += fromSeconds(options.association.time_offset_s);
        const std::optional<ForceErrors> with_total = forceErrors(*gt.forces, total, max_diff);
        if (with_total) r.force->total = with_total->total;
        else r.notes.push_back("force: no ground-truth force at the total force's stamps");
      }
    }
  }
  return r;
}

}  // namespace hdvio::eval
