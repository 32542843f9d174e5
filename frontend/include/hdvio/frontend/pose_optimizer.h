#pragma once
// Motion-only and structure-only refinement after feature alignment: Gauss-Newton on the
// reprojection error in the normalized image plane with a Huber kernel, written in Eigen.
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio::frontend {

struct PoseObservation {
  Vec3 p_w;        // landmark
  Vec3 f;          // measured unit bearing in the camera
  int level = 0;   // measurement noise grows with the pyramid level
};

struct PoseOptimizerOptions {
  int iterations = 10;
  double huber_px = 1.5;          // kernel width, level-0 pixels
  double outlier_px = 2.5;        // observations above this (times 2^level) are rejected
};

struct PoseOptimizerResult {
  Pose T_cw;
  std::vector<char> inlier;  // per observation
  int inliers = 0;
  double rms_px = 0.0;       // over inliers, level-0 pixels
};

PoseOptimizerResult optimizePose(const Pose& T_cw_guess, const std::vector<PoseObservation>& obs,
                                 double focal_length, const PoseOptimizerOptions& options);

struct PointObservation {
  Pose T_cw;
  Vec3 f;
};

// Refines one landmark from its observations; returns false (p_w unchanged) if the error
// did not decrease or the point ends up behind a camera.
bool optimizePoint(const std::vector<PointObservation>& obs, int iterations, Vec3* p_w);

}  // namespace hdvio::frontend
