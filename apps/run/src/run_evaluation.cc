#include "hdvio/run/run_evaluation.h"

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <yaml-cpp/yaml.h>

#include "hdvio/core/error.h"
#include "hdvio/eval/estimate_inputs.h"
#include "hdvio/eval/report.h"
#include "hdvio/io/sequence_reader.h"

namespace hdvio::run {
namespace fs = std::filesystem;

namespace {

bool isAslWithGroundTruth(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  return fs::exists(p / "mav0" / "state_groundtruth_estimate0" / "data.csv", ec) ||
         fs::exists(p / "state_groundtruth_estimate0" / "data.csv", ec);
}

eval::GroundTruth groundTruthFromSequence(const Sequence& seq) {
  eval::GroundTruth gt;
  eval::Trajectory& t = gt.trajectory;
  t.source = seq.source;
  t.reserve(seq.groundtruth.size());
  bool all_velocity = true;
  for (const GroundTruthState& s : seq.groundtruth) {
    t.push(s.t, s.T_WB.p, s.T_WB.q.toRotationMatrix());
    all_velocity = all_velocity && s.has_velocity;
  }
  if (all_velocity)
    for (const GroundTruthState& s : seq.groundtruth) t.v.push_back(s.v_W);
  if (!seq.forces.empty()) {
    eval::ForceGroundTruth f;
    f.source = seq.source;
    for (const ForceSample& s : seq.forces) {
      f.t.push_back(s.t);
      f.external.push_back(s.external);
      f.drag.push_back(s.drag);
    }
    gt.forces = std::move(f);
  }
  return gt;
}

// The method of the result's effective config, else the folder name; estimate names allow
// letters, digits and _ - . (hdvio_eval's rule).
std::string estimateName(const std::string& results_dir) {
  std::string name;
  try {
    const YAML::Node cfg = YAML::LoadFile((fs::path(results_dir) / "config.yaml").string());
    if (cfg["method"] && cfg["method"].IsScalar()) name = cfg["method"].Scalar();
  } catch (const YAML::Exception&) {
  }
  if (name.empty()) name = fs::path(results_dir).lexically_normal().filename().string();
  if (name.empty()) name = fs::path(results_dir).lexically_normal().parent_path().filename().string();
  std::string out;
  for (char c : name)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') ? c : '_';
  return out.empty() ? "estimate" : out;
}

std::string sourceDirOfBuildTree(fs::path dir) {
  for (int up = 0; up < 6 && !dir.empty(); ++up, dir = dir.parent_path()) {
    std::ifstream cache(dir / "CMakeCache.txt");
    if (!cache) {
      if (dir == dir.parent_path()) break;
      continue;
    }
    std::string line;
    const std::string key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
    while (std::getline(cache, line))
      if (line.rfind(key, 0) == 0) return line.substr(key.size());
    return "";
  }
  return "";
}

}  // namespace

std::optional<eval::GroundTruth> loadRunGroundTruth(const std::string& dataset_path,
                                                    const Sequence* seq) {
  if (isAslWithGroundTruth(dataset_path))
    return eval::loadGroundTruth(dataset_path, eval::TrajectoryFormat::kAuto, std::nullopt);
  if (seq) {
    if (!seq->hasGroundTruth()) return std::nullopt;
    return groundTruthFromSequence(*seq);
  }
  const Sequence read = io::readSequence(dataset_path);
  if (!read.hasGroundTruth()) return std::nullopt;
  return groundTruthFromSequence(read);
}

std::string findEvalPlotScript() {
  if (const char* env = std::getenv("HDVIO_EVAL_PLOT_SCRIPT"); env && fs::exists(env)) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  if (fs::exists(exe.parent_path() / "plot_evaluation.py", ec))
    return (exe.parent_path() / "plot_evaluation.py").string();
  const std::string src = sourceDirOfBuildTree(exe.parent_path());
  if (!src.empty() && fs::exists(fs::path(src) / "apps/eval/plot_evaluation.py", ec))
    return (fs::path(src) / "apps/eval/plot_evaluation.py").string();
  return "";
}

bool evaluateRun(const Sequence& seq, const std::string& dataset_path,
                 const std::string& results_dir, const RunEvaluationOptions& options) {
  const fs::path out_dir = fs::path(results_dir) / "evaluation";
  try {
    const std::optional<eval::GroundTruth> gt = loadRunGroundTruth(dataset_path, &seq);
    if (!gt) {
      std::fprintf(stderr, "hdvio_run: the sequence has no ground truth; nothing evaluated\n");
      return false;
    }
    eval::EvaluationOptions eo;
    eo.alignment = options.alignment;
    const eval::Estimate est = eval::loadEstimate(
        eval::resultFolderSpec(estimateName(results_dir), results_dir), eval::TrajectoryFormat::kAuto);
    eval::EvaluationReport report;
    report.ground_truth_source = dataset_path;
    report.options = eo;
    for (const eval::Trajectory* traj : {&gt->trajectory, &est.trajectory})
      if (traj->repeated_stamps > 0) std::fprintf(stderr, "hdvio_run: %s\n", eval::repeatedStampsWarning(*traj).c_str());
    // The fractions are of the ground truth's length over the run's span (rpg with a
    // start_end_time.yaml); the matching itself uses all of it, so ATE does not change.
    eval::GroundTruth span;
    if (options.ground_truth_span)
      span.trajectory = gt->trajectory.between(options.ground_truth_span->first,
                                               options.ground_truth_span->second);
    report.distances = eval::relativeErrorDistances(options.ground_truth_span ? span : *gt, eo);
    report.results.push_back(eval::evaluateEstimate(*gt, est, eo, report.distances));
    eval::writeReport(report, *gt, out_dir.string());
    std::cout << eval::formatTable(report) << std::flush;
  } catch (const std::exception& e) {
    // The estimate itself is complete; a failed evaluation must not hide it.
    std::fprintf(stderr,
                 "hdvio_run: evaluation failed (the run's results in %s are complete): %s\n",
                 results_dir.c_str(), e.what());
    return false;
  }
  std::fprintf(stderr, "hdvio_run: evaluation in %s\n", out_dir.string().c_str());
  if (!options.plots) return true;
  const std::string script = findEvalPlotScript();
  if (script.empty()) {
    std::fprintf(stderr, "hdvio_run: note: figures skipped, plot_evaluation.py not found "
                         "(set HDVIO_EVAL_PLOT_SCRIPT)\n");
    return true;
  }
  if (std::system("/usr/bin/python3 -c 'import matplotlib, numpy' > /dev/null 2>&1") != 0) {
    std::fprintf(stderr, "hdvio_run: note: figures skipped, /usr/bin/python3 with matplotlib "
                         "and numpy is needed (Debian: python3-matplotlib)\n");
    return true;
  }
  const std::string cmd =
      "/usr/bin/python3 '" + script + "' --dir '" + out_dir.string() + "' > /dev/null";
  if (std::system(cmd.c_str()) != 0)
    std::fprintf(stderr, "hdvio_run: note: plotting failed: %s\n", cmd.c_str());
  return true;
}

}  // namespace hdvio::run
