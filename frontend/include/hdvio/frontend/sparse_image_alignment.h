#pragma once
// Sparse image alignment (SVO): the relative pose T_cur_ref that minimizes the photometric
// error of small patches around known 3-D points, by inverse-compositional Gauss-Newton from a
// coarse to a fine pyramid level. The reference patches and their Jacobians are computed once
// per level; an optional IMU rotation prior regularizes the rotation.
#include <optional>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/pyramid.h"

namespace hdvio::frontend {

struct SparseAlignmentOptions {
  int max_level = 4;            // coarsest pyramid level used
  int min_level = 2;            // finest pyramid level used
  int max_iterations = 30;      // per level
  double huber_threshold = 15.0;        // intensity units
  double intensity_sigma = 8.0;         // photometric noise, weighs the rotation prior
  double rotation_prior_sigma = 0.02;   // rad, standard deviation of the IMU rotation prior
};

struct SparseAlignmentResult {
  Pose T_cur_ref;
  int patches = 0;          // patches inside the image at the finest level
  double rms_error = 0.0;   // intensity RMS at the finest level
  bool ok = false;          // enough patches and a finite solution
};

// points_ref: 3-D points in the reference camera frame (visible in the reference image).
// rotation_prior: R_cur_ref predicted from the gyroscope, if known.
SparseAlignmentResult alignSparse(const CameraModel& camera, const Pyramid& ref,
                                  const std::vector<Vec3>& points_ref, const Pyramid& cur,
                                  const Pose& T_cur_ref_guess,
                                  const std::optional<Quat>& rotation_prior,
                                  const SparseAlignmentOptions& options);

}  // namespace hdvio::frontend
