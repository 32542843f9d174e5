#pragma once
// Alignment of an estimate to ground truth before absolute errors are computed:
// ref ~= s * R * est + t. Implements the rpg toolbox's choices (posyaw default for VIO, where
// yaw and position are unobservable) and evo's Umeyama (SE(3), Sim(3)).
#include <string>
#include <vector>

#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

enum class AlignmentType { kNone, kPosYaw, kSE3, kSim3 };

AlignmentType parseAlignmentType(const std::string& name);  // "none|posyaw|se3|sim3"
std::string alignmentName(AlignmentType type);

struct SimilarityTransform {
  double s = 1.0;
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  Vec3 apply(const Vec3& x) const { return s * (R * x) + t; }
};

// Umeyama (1991) least squares fit of ref ~= s R est + t over corresponding points, the
// algorithm evo's umeyama_alignment implements. Throws InputError for degenerate point sets.
SimilarityTransform umeyamaAlignment(const std::vector<Vec3>& est, const std::vector<Vec3>& ref,
                                     bool with_scale);

// The rpg toolbox's yaw-only Umeyama: rotation about world z and translation, scale 1.
SimilarityTransform positionYawAlignment(const std::vector<Vec3>& est, const std::vector<Vec3>& ref);

// The rpg toolbox's single-pose posyaw: the yaw that best maps the first estimated orientation
// onto the first true one, translation matching the first positions.
SimilarityTransform positionYawFromFirstPose(const Mat3& R_est, const Vec3& p_est,
                                             const Mat3& R_ref, const Vec3& p_ref);

// Alignment from the first `first_n` associated poses (<= 0: all), as rpg's align_num_frames.
// posyaw with first_n == 1 uses the single-pose variant, like the rpg toolbox.
SimilarityTransform computeAlignment(AlignmentType type, const Trajectory& ref,
                                     const Trajectory& est, int first_n);

// p -> s R p + t, R_WB -> R R_WB, v -> s R v.
Trajectory applyAlignment(const SimilarityTransform& T, const Trajectory& est);

}  // namespace hdvio::eval
