#pragma once
// Absolute and relative pose errors on associated trajectories (ref[i] belongs to est[i]).
//  - absolute: evo's APE translation part (|p_est - p_ref| after alignment) and the rotation
//    angle of R_est^T R_ref in degrees (the same angle the rpg toolbox reports).
//  - evo RPE: pairs by a delta in frames or in meters of travelled path, errors of
//    E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with evo's matrix arithmetic.
//  - rpg relative error: sub-trajectories of fixed length along the ground-truth path
//    (compute_relative_error of the rpg trajectory evaluation toolbox).
#include <utility>
#include <vector>

#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

// Rotation angle of a (near-)rotation matrix in degrees, in [0, 180].
double rotationAngleDeg(const Mat3& R);

struct AbsoluteErrors {
  std::vector<double> translation;   // m
  std::vector<double> rotation_deg;  // deg
};
AbsoluteErrors absoluteErrors(const Trajectory& ref, const Trajectory& est_aligned);

enum class DeltaUnit { kFrames, kMeters };
DeltaUnit parseDeltaUnit(const std::string& name);  // "f" | "m"

struct EvoRpeOptions {
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::kFrames;
  bool all_pairs = false;
  double rel_delta_tol = 0.1;          // all_pairs with meters: accept |path - delta| <= tol*delta
  bool pairs_from_reference = false;   // evo's default picks pairs on the estimate's path
};

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

// evo's filters.id_pairs_from_delta (empty when the trajectory is too short for delta).
IndexPairs evoPairs(const std::vector<Vec3>& positions, const EvoRpeOptions& options);

struct RelativeErrors {
  IndexPairs pairs;
  std::vector<double> translation;   // m
  std::vector<double> rotation_deg;  // deg
};
RelativeErrors evoRelativeErrors(const Trajectory& ref, const Trajectory& est,
                                 const EvoRpeOptions& options);

// One sub-trajectory length of the rpg relative error.
struct RpgRelativeError {
  double distance = 0.0;              // sub-trajectory length, m
  std::vector<std::size_t> start_ids;
  std::vector<double> translation;    // m
  std::vector<double> translation_percent;
  std::vector<double> rotation_deg;
  std::vector<double> yaw_deg;
  std::vector<double> gravity_deg;    // roll/pitch part of the rotation error
};

// compute_relative_error with T_cm = identity; `scale` multiplies the estimated relative
// translations (the Sim(3) scale, 1 otherwise). max_dist_diff <= 0 means 0.2 * distance.
RpgRelativeError rpgRelativeError(const Trajectory& ref, const Trajectory& est, double distance,
                                  double max_dist_diff = -1.0, double scale = 1.0);

// The rpg toolbox's preset sub-trajectory lengths: trunc(fraction * length, 2 decimals).
std::vector<double> rpgDistancesFromFractions(double trajectory_length,
                                              const std::vector<double>& fractions);

}  // namespace hdvio::eval
