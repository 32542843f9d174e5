#pragma once
// Visual-inertial alignment (Qin et al., VINS-Mono, T-RO 2018, Sec. V-B): given body rotations
// and up-to-scale camera positions from visual SfM in the first camera frame C0, and the
// preintegrated IMU between consecutive frames, recover the gyro bias, every frame's velocity,
// gravity in C0 and the metric scale by linear least squares; then refine gravity on the
// sphere |g| = 9.81 (optionally with the accelerometer bias).
#include <string>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/factors/imu_preintegration.h"

namespace hdvio::vi_init {

struct AlignmentFrame {
  Mat3 R_C0B;  // body rotation in the first camera frame (from SfM, exact up to noise)
  Vec3 p_C0C;  // camera position in the first camera frame, up to scale
};

// Gyro bias that makes the preintegrated rotations between consecutive frames agree with the
// visual ones (linearized once around each preintegration's own bias); preint[k] covers
// frames k -> k+1.
Vec3 estimateGyroBias(const std::vector<AlignmentFrame>& frames,
                      const std::vector<PreintegratedImu>& preint);

struct AlignmentOptions {
  bool estimate_accel_bias = false;  // only in the refinement; a weak prior keeps it near 0
  double accel_bias_prior_sigma = 0.2;  // m/s^2
  double equation_sigma = 0.02;  // m and m/s: assumed noise of the alignment equations
  int refinement_iterations = 4;
};

struct AlignmentResult {
  double scale = 0.0;                  // metres per SfM unit
  double scale_relative_std = 0.0;     // from the residual and the normal equations
  Vec3 g_C0 = Vec3::Zero();            // gravity (pointing down) in the first camera frame
  std::vector<Vec3> v_C0;              // body velocity of every frame in C0
  Vec3 accel_bias_delta = Vec3::Zero(); // relative to the preintegration's accel bias
  double rms_residual = 0.0;           // of the stacked equations (m, m/s)
};

// Linear alignment with free gravity (3 unknowns); p_BC: camera position in the body frame.
AlignmentResult alignLinear(const std::vector<AlignmentFrame>& frames,
                            const std::vector<PreintegratedImu>& preint, const Vec3& p_BC);

// Gravity refinement with |g| fixed, starting from g_init (e.g. alignLinear's).
AlignmentResult refineGravity(const std::vector<AlignmentFrame>& frames,
                              const std::vector<PreintegratedImu>& preint, const Vec3& p_BC,
                              const Vec3& g_init, const AlignmentOptions& options);

// Two unit vectors spanning the plane orthogonal to g.
Eigen::Matrix<double, 3, 2> tangentBasis(const Vec3& g);

}  // namespace hdvio::vi_init
