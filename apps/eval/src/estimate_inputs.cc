#include "hdvio/eval/estimate_inputs.h"

#include <cctype>
#include <filesystem>
#include <set>

#include "hdvio/core/error.h"

namespace hdvio::eval {
namespace fs = std::filesystem;
namespace {

const char* const kTrajectoryNames[] = {"stamped_traj_estimate.txt"};
const char* const kVelocityNames[] = {"stamped_velocity_estimate.csv", "velocity_estimate.csv",
                                      "velocity.csv"};
const char* const kForceNames[] = {"stamped_force_estimate.csv", "force_estimate.csv",
                                   "external_force_estimate.csv", "force.csv"};
const char* const kTotalForceNames[] = {"stamped_total_force_estimate.csv"};

template <std::size_t N>
std::optional<std::string> firstExisting(const fs::path& dir, const char* const (&names)[N]) {
  for (const char* name : names)
    if (fs::exists(dir / name)) return (dir / name).string();
  return std::nullopt;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = s.find(sep, start);
    parts.push_back(s.substr(start, pos == std::string::npos ? std::string::npos : pos - start));
    if (pos == std::string::npos) return parts;
    start = pos + 1;
  }
}

bool validName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return true;
}

}  // namespace

std::vector<EstimateSpec> parseEstimateList(const std::string& list) {
  if (list.empty()) throw InputError("--est", 0, "no estimate given");
  std::vector<EstimateSpec> specs;
  std::set<std::string> names;
  for (const std::string& item : split(list, ',')) {
    const std::vector<std::string> parts = split(item, ':');
    EstimateSpec spec;
    const std::size_t eq = parts[0].find('=');
    if (eq == std::string::npos) {
      spec.path = parts[0];
      spec.name = fs::path(spec.path).filename().stem().string();
      if (spec.name == "stamped_traj_estimate" || spec.name.empty())
        spec.name = "est" + std::to_string(specs.size() + 1);
    } else {
      spec.name = parts[0].substr(0, eq);
      spec.path = parts[0].substr(eq + 1);
    }
    if (!validName(spec.name))
      throw InputError("--est", 0, "bad estimate name '" + spec.name + "' (use letters, digits, _ - .)");
    if (spec.path.empty()) throw InputError("--est", 0, "estimate '" + spec.name + "' has no path");
    if (!names.insert(spec.name).second)
      throw InputError("--est", 0, "estimate name '" + spec.name + "' given twice");
    for (std::size_t i = 1; i < parts.size(); ++i) {
      const std::size_t e = parts[i].find('=');
      const std::string key = parts[i].substr(0, e);
      const std::string value = e == std::string::npos ? "" : parts[i].substr(e + 1);
      if (value.empty()) throw InputError("--est", 0, "'" + parts[i] + "' needs key=file");
      if (key == "velocity") spec.velocity_path = value;
      else if (key == "force") spec.force_path = value;
      else if (key == "total_force") spec.total_force_path = value;
      else throw InputError("--est", 0,
                            "unknown estimate option '" + key + "' (velocity|force|total_force)");
    }
    specs.push_back(spec);
  }
  return specs;
}

Estimate loadEstimate(const EstimateSpec& spec, TrajectoryFormat format) {
  Estimate est;
  est.name = spec.name;
  std::string trajectory_path = spec.path;
  std::optional<std::string> velocity_path = spec.velocity_path;
  std::optional<std::string> force_path = spec.force_path;
  std::optional<std::string> total_force_path = spec.total_force_path;
  const bool asl = format == TrajectoryFormat::kAslFolder ||
                   (format == TrajectoryFormat::kAuto && fs::exists(fs::path(spec.path) / "mav0"));
  if (fs::is_directory(spec.path) && !asl) {
    const auto found = firstExisting(spec.path, kTrajectoryNames);
    if (!found) throw InputError(spec.path, 0, "result folder has no stamped_traj_estimate.txt");
    trajectory_path = *found;
    if (!velocity_path) velocity_path = firstExisting(spec.path, kVelocityNames);
    // An explicit force= file alone keeps its old meaning (both force columns from it).
    if (!force_path) {
      force_path = firstExisting(spec.path, kForceNames);
      if (!total_force_path) total_force_path = firstExisting(spec.path, kTotalForceNames);
    }
  }
  est.trajectory = readTrajectory(trajectory_path, format);
  if (velocity_path) est.velocity = readVectorSeries(*velocity_path);
  if (force_path) est.force = readVectorSeries(*force_path);
  if (total_force_path) {
    if (!est.force)
      throw InputError(*total_force_path, 0, "a total force needs the external force (force=) too");
    est.total_force = readVectorSeries(*total_force_path);
  }
  return est;
}

GroundTruth loadGroundTruth(const std::string& path, TrajectoryFormat format,
                            const std::optional<std::string>& force_path) {
  GroundTruth gt;
  gt.trajectory = readTrajectory(path, format);
  std::optional<std::string> forces = force_path;
  if (!forces && fs::is_directory(path)) forces = aslForceGroundTruthPath(path);
  if (forces) gt.forces = readForceGroundTruth(*forces);
  return gt;
}

}  // namespace hdvio::eval
