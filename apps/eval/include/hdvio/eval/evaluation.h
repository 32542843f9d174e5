#pragma once
// One evaluation run: ground truth, any number of estimates, the same options for all of them
// so their numbers can stand side by side.
#include <optional>
#include <string>
#include <vector>

#include "hdvio/eval/alignment.h"
#include "hdvio/eval/association.h"
#include "hdvio/eval/pose_errors.h"
#include "hdvio/eval/signal_errors.h"
#include "hdvio/eval/statistics.h"
#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

struct EvaluationOptions {
  AssociationOptions association;
  AlignmentType alignment = AlignmentType::kPosYaw;
  int align_first_n = -1;                      // <= 0: all associated poses
  std::vector<double> rpe_distances_m;         // fixed sub-trajectory lengths (rpg)
  std::vector<double> rpe_fractions = {0.1, 0.2, 0.3, 0.4, 0.5};  // of the gt length (rpg)
  bool evo_rpe = true;
  EvoRpeOptions evo_rpe_options{10.0, DeltaUnit::kMeters, false, 0.1, false};
};

struct GroundTruth {
  Trajectory trajectory;
  std::optional<ForceGroundTruth> forces;
};

struct Estimate {
  std::string name;
  Trajectory trajectory;
  std::optional<VectorSeries> velocity;  // falls back to the trajectory's own velocity column
  std::optional<VectorSeries> force;        // external force f_ext (IMU frame)
  // Total non-thrust force (f_res + f_ext, IMU frame) when the estimator writes it separately
  // (hdvio with a learned residual force); the "total" force errors use it, else `force`.
  std::optional<VectorSeries> total_force;
};

struct RelativeErrorSummary {
  double distance = 0.0;
  RpgRelativeError errors;
  ErrorStatistics translation, translation_percent, rotation_deg, yaw_deg;
};

struct EstimateResult {
  std::string name;
  std::string source;
  std::size_t num_poses = 0;
  std::size_t num_matched = 0;
  SimilarityTransform alignment;
  Trajectory ref_matched;   // ground truth at the matched stamps
  Trajectory est_aligned;   // matched estimate after alignment
  AbsoluteErrors ate;
  ErrorStatistics ate_translation, ate_rotation_deg;
  std::optional<RelativeErrors> evo_rpe;
  ErrorStatistics evo_rpe_translation, evo_rpe_rotation_deg;
  std::vector<RelativeErrorSummary> relative;  // one per sub-trajectory length
  std::optional<VectorErrors> velocity;
  std::optional<ForceErrors> force;
  std::vector<std::string> notes;  // why a metric is missing
};

// Sub-trajectory lengths: the fixed ones, then the fractions of the ground truth's length
// (computed on the full ground truth, as the rpg toolbox does), sorted, duplicates removed.
std::vector<double> relativeErrorDistances(const GroundTruth& gt, const EvaluationOptions& options);

EstimateResult evaluateEstimate(const GroundTruth& gt, const Estimate& est,
                                const EvaluationOptions& options,
                                const std::vector<double>& distances);

}  // namespace hdvio::eval
