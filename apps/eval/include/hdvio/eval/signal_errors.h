#pragma once
// Errors of estimated 3-vector signals against ground truth: velocity (world frame, after the
// trajectory alignment) and mass-normalized forces (IMU frame, no alignment).
#include <optional>
#include <vector>

#include "hdvio/eval/alignment.h"
#include "hdvio/eval/statistics.h"
#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

// Errors of one signal split like the force tables of hybrid-dynamics VIO papers.
struct VectorErrors {
  std::vector<Timestamp> t;        // stamps of the matched estimate samples
  std::vector<Vec3> estimate;      // matched estimate samples
  std::vector<Vec3> truth;         // matched ground truth
  ErrorStatistics total;           // |e|
  ErrorStatistics xy;              // |(e_x, e_y)|
  ErrorStatistics z;               // |e_z|
};

VectorErrors vectorErrors(const std::vector<Timestamp>& t, const std::vector<Vec3>& estimate,
                          const std::vector<Vec3>& truth);

// Estimated velocities against the ground-truth trajectory's velocities, matched to the nearest
// stamp within max_diff; the estimate is rotated (and scaled) by the trajectory alignment.
std::optional<VectorErrors> velocityErrors(const Trajectory& gt, const VectorSeries& est,
                                           const SimilarityTransform& alignment,
                                           Timestamp max_diff_ns);

struct ForceErrors {
  VectorErrors external;  // estimate vs f_ext
  VectorErrors total;     // estimate vs f_ext + f_drag (all non-thrust force)
};

std::optional<ForceErrors> forceErrors(const ForceGroundTruth& gt, const VectorSeries& est,
                                       Timestamp max_diff_ns);

}  // namespace hdvio::eval
