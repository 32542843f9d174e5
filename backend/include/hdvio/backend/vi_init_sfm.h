#pragma once
// Visual structure from motion up to scale over a short window of frames, the first step of
// visual-inertial initialization. The gauge: the first camera is the origin with identity
// rotation and the reference frame (the one with most parallax to the first) sits at unit
// distance. Gyro-integrated rotations seed every step; the final bundle adjustment frees them,
// so the visual rotations can then calibrate the gyro bias.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio::vi_init {

// Undistorted unit bearing vectors (camera frame) of one frame, by landmark id.
struct BearingFrame {
  std::map<int, Vec3> bearings;
};

struct SfmOptions {
  int min_common_tracks = 20;        // tracks shared by the first and the reference frame
  double min_parallax_rad = 0.02;    // median rotation-compensated parallax of that pair
  double inlier_threshold_px = 2.0;  // epipolar / reprojection error of an inlier
  int ransac_iterations = 200;
  std::uint32_t seed = 1;            // fixed: the result is deterministic
  int min_pnp_points = 8;
  int min_landmarks = 20;            // triangulated points after bundle adjustment
};

struct SfmResult {
  bool success = false;
  std::string reason;                   // why it failed
  std::vector<Pose> T_C0C;              // camera k in the first camera frame (up to scale)
  std::map<int, Vec3> points_C0;        // landmarks in the first camera frame (same scale)
  int reference_frame = -1;
  double reference_parallax_rad = 0.0;  // median rotation-compensated parallax
  double rms_reprojection_px = 0.0;     // after bundle adjustment, inliers
  int inlier_observations = 0;
};

// frames: bearings per frame; R_C0C_prior: camera rotations relative to the first camera from
// the gyro (any bias error is tolerated, they only seed the solution); focal_px: pixels per
// unit of the normalized image plane, to express thresholds in pixels.
SfmResult reconstructUpToScale(const std::vector<BearingFrame>& frames,
                               const std::vector<Mat3>& R_C0C_prior, double focal_px,
                               const SfmOptions& options);

// Median angle between the bearings of common landmarks after removing the rotation that best
// aligns them (least squares); 0 with fewer than three. Pure rotation gives ~0.
double medianParallax(const BearingFrame& a, const BearingFrame& b, int* common = nullptr);

}  // namespace hdvio::vi_init
