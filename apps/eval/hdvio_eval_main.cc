// hdvio_eval: evo / rpg-toolbox style trajectory evaluation of one or more estimates against
// ground truth, as a table, JSON and (with --plots) PNG figures.
#include <gflags/gflags.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/eval/estimate_inputs.h"
#include "hdvio/eval/evaluation.h"
#include "hdvio/eval/report.h"

DEFINE_string(gt, "", "ground truth: TUM-order file, EuRoC CSV, KITTI poses or ASL sequence folder");
DEFINE_string(gt_format, "auto", "auto|tum|kitti|euroc|asl");
DEFINE_string(force_gt, "", "force_groundtruth0 CSV (default: the ASL folder's, if any)");
DEFINE_string(est, "", "comma-separated name=path[:velocity=csv][:force=csv][:total_force=csv]; path "
                       "is a file or a result folder with stamped_traj_estimate.txt");
DEFINE_string(est_format, "auto", "auto|tum|kitti|euroc|asl");
DEFINE_string(align, "posyaw", "none|posyaw|se3|sim3");
DEFINE_int32(align_first_n, -1, "align on the first n associated poses (-1: all)");
DEFINE_string(association, "", "timestamp|interpolate|index (default: index for KITTI files, else timestamp)");
DEFINE_double(max_time_diff, 0.01, "association tolerance, s");
DEFINE_double(time_offset, 0.0, "added to the estimate's stamps, s");
DEFINE_string(rpe_distances, "", "fixed sub-trajectory lengths in m, comma-separated (rpg)");
DEFINE_string(rpe_fractions, "0.1,0.2,0.3,0.4,0.5", "sub-trajectory lengths as fractions of the gt length (rpg); empty for none");
DEFINE_double(evo_rpe_delta, 10.0, "evo RPE delta (0 disables)");
DEFINE_string(evo_rpe_unit, "m", "evo RPE delta unit: m|f");
DEFINE_bool(evo_rpe_all_pairs, false, "evo RPE with all pairs instead of consecutive ones");
DEFINE_string(out, "", "output folder (table.md, metrics.json, plot_data/, figures)");
DEFINE_bool(plots, false, "make PNG figures with python3 + matplotlib");
DEFINE_string(python, "/usr/bin/python3", "python interpreter for --plots");
DEFINE_string(plot_script, HDVIO_EVAL_PLOT_SCRIPT, "plot script for --plots");

namespace {

using hdvio::InputError;

std::vector<double> parseNumberList(const std::string& flag, const std::string& text) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end != item.c_str() + item.size() || !(v > 0.0) || !std::isfinite(v))
      throw InputError("--" + flag, 0, "expected positive numbers, got '" + item + "'");
    values.push_back(v);
  }
  return values;
}

int runPlots(const std::string& out_dir) {
  std::cout.flush();  // keep the table before the script's own output
  const std::string check = "'" + FLAGS_python + "' -c 'import matplotlib, numpy' > /dev/null 2>&1";
  if (std::system(check.c_str()) != 0) {
    std::cerr << "error: --plots needs " << FLAGS_python
              << " with matplotlib and numpy (Debian: python3-matplotlib)\n";
    return 1;
  }
  if (!std::filesystem::exists(FLAGS_plot_script)) {
    std::cerr << "error: plot script not found: " << FLAGS_plot_script << "\n";
    return 1;
  }
  const std::string cmd = "'" + FLAGS_python + "' '" + FLAGS_plot_script + "' --dir '" + out_dir + "'";
  if (std::system(cmd.c_str()) != 0) {
    std::cerr << "error: plotting failed: " << cmd << "\n";
    return 1;
  }
  return 0;
}

int run() {
  using namespace hdvio::eval;
  if (FLAGS_plots && FLAGS_out.empty()) throw hdvio::InputError("", 0, "--plots needs --out");
  const TrajectoryFormat gt_format = parseTrajectoryFormat(FLAGS_gt_format);
  const TrajectoryFormat est_format = parseTrajectoryFormat(FLAGS_est_format);
  EvaluationOptions options;
  options.alignment = parseAlignmentType(FLAGS_align);
  options.align_first_n = FLAGS_align_first_n;
  if (!(FLAGS_max_time_diff > 0.0)) throw InputError("--max_time_diff", 0, "must be positive");
  options.association.max_time_diff_s = FLAGS_max_time_diff;
  options.association.time_offset_s = FLAGS_time_offset;
  options.rpe_distances_m = parseNumberList("rpe_distances", FLAGS_rpe_distances);
  options.rpe_fractions = parseNumberList("rpe_fractions", FLAGS_rpe_fractions);
  options.evo_rpe = FLAGS_evo_rpe_delta > 0.0;
  options.evo_rpe_options.delta = FLAGS_evo_rpe_delta;
  options.evo_rpe_options.unit = parseDeltaUnit(FLAGS_evo_rpe_unit);
  options.evo_rpe_options.all_pairs = FLAGS_evo_rpe_all_pairs;
  const std::vector<EstimateSpec> specs = parseEstimateList(FLAGS_est);

  // Read and evaluate everything before writing anything.
  const GroundTruth gt = loadGroundTruth(
      FLAGS_gt, gt_format, FLAGS_force_gt.empty() ? std::nullopt : std::optional<std::string>(FLAGS_force_gt));
  std::vector<Estimate> estimates;
  for (const EstimateSpec& spec : specs) estimates.push_back(loadEstimate(spec, est_format));
  std::vector<const Trajectory*> read{&gt.trajectory};
  for (const Estimate& e : estimates) read.push_back(&e.trajectory);
  for (const Trajectory* traj : read)
    if (traj->repeated_stamps > 0) std::cerr << repeatedStampsWarning(*traj) << "\n";
  if (FLAGS_association.empty()) {
    bool indexed = !gt.trajectory.has_timestamps;
    for (const auto& e : estimates) indexed = indexed || !e.trajectory.has_timestamps;
    options.association.mode = indexed ? AssociationMode::kIndex : AssociationMode::kTimestamp;
  } else {
    options.association.mode = parseAssociationMode(FLAGS_association);
  }

  EvaluationReport report;
  report.ground_truth_source = FLAGS_gt;
  report.options = options;
  report.distances = relativeErrorDistances(gt, options);
  for (const Estimate& e : estimates)
    report.results.push_back(evaluateEstimate(gt, e, options, report.distances));

  std::cout << formatTable(report);
  if (FLAGS_out.empty()) return 0;
  writeReport(report, gt, FLAGS_out);
  std::cout << "wrote " << FLAGS_out << "/table.md and metrics.json\n";
  if (FLAGS_plots) return runPlots(FLAGS_out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_eval --gt <file|asl folder> --est name1=path1[,name2=path2...] [--align se3] [--out dir [--plots]]\n"
      "trajectory evaluation with evo / rpg toolbox metrics (ATE, RPE)\n"
      "example: hdvio_eval --gt ../shared/data/euroc/V1_01_easy_excerpt --est vio=/tmp/vio --align se3");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_gt, FLAGS_est}, true, "--gt and --est are required"))
    return bad;
  return hdvio::runTool(run);
}
