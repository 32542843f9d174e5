#pragma once
// Pairs estimate poses with ground-truth poses. The result is two trajectories of equal length
// whose i-th poses belong together.
#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

enum class AssociationMode {
  kTimestamp,    // nearest stamp within a tolerance, evo's associate_trajectories
  kInterpolate,  // ground truth interpolated at the estimate's stamps (lerp p and v, slerp R)
  kIndex,        // i-th pose with i-th pose (KITTI files); both must have the same length
};

AssociationMode parseAssociationMode(const std::string& name);  // "timestamp|interpolate|index"
std::string associationName(AssociationMode mode);

struct AssociationOptions {
  AssociationMode mode = AssociationMode::kTimestamp;
  double max_time_diff_s = 0.01;  // evo's default --t_max_diff
  double time_offset_s = 0.0;     // added to the estimate's stamps
};

struct AssociatedPair {
  Trajectory ref;
  Trajectory est;
};

// Throws InputError when nothing matches or index association sees different lengths.
AssociatedPair associate(const Trajectory& ref, const Trajectory& est, const AssociationOptions& options);

// evo's matching_time_indices: for every stamp of `a`, the nearest stamp of `b` (first one on a
// tie), kept when |diff| <= max_diff_ns. Indices of `b` may repeat, as in evo.
void matchNearestStamps(const std::vector<Timestamp>& a, const std::vector<Timestamp>& b,
                        Timestamp max_diff_ns, std::vector<std::size_t>* ids_a,
                        std::vector<std::size_t>* ids_b);

// Nearest-stamp lookup of a vector signal; false if nothing lies within max_diff_ns.
bool nearestIndex(const std::vector<Timestamp>& stamps, Timestamp t, Timestamp max_diff_ns,
                  std::size_t* index);

}  // namespace hdvio::eval
