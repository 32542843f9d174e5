#pragma once
// Turning the tool's arguments into loaded inputs. An estimate is given as
//   name=path[:velocity=file][:force=file][:total_force=file]
// where path is a trajectory file or a result folder holding stamped_traj_estimate.txt and,
// optionally, velocity/force CSVs under their usual names. force= is the external force (also
// used for the total-force errors unless a total force is given); total_force= the total
// non-thrust force f_res + f_ext (a result folder's stamped_total_force_estimate.csv is picked up
// unless force= is given alone). Several estimates are separated by
// commas (gflags cannot repeat a flag).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hdvio/eval/evaluation.h"
#include "hdvio/eval/trajectory_io.h"

namespace hdvio::eval {

struct EstimateSpec {
  std::string name;
  std::string path;
  std::optional<std::string> velocity_path;
  std::optional<std::string> force_path;
  std::optional<std::string> total_force_path;
};

// A run's result folder: its velocity and force files are found in it by loadEstimate.
inline EstimateSpec resultFolderSpec(std::string name, std::string dir) {
  EstimateSpec spec;
  spec.name = std::move(name);
  spec.path = std::move(dir);
  return spec;
}

// Throws InputError for empty lists, bad names (allowed: letters, digits, _ - .) and duplicates.
std::vector<EstimateSpec> parseEstimateList(const std::string& list);

Estimate loadEstimate(const EstimateSpec& spec, TrajectoryFormat format);

// Ground truth from a file or an ASL folder; force ground truth from force_path when given,
// else from the ASL folder's force_groundtruth0 when it has one.
GroundTruth loadGroundTruth(const std::string& path, TrajectoryFormat format,
                            const std::optional<std::string>& force_path);

}  // namespace hdvio::eval
