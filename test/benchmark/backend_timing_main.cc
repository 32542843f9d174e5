// hdvio_backend_bench --dataset <ASL folder with landmark tracks> --config <experiment.yaml>
// Times the sliding-window backend frame by frame on one thread (CPU time of the thread, so
// other jobs on the machine inflate it little) and prints median / p90 / max per frame and per
// keyframe update, the window size and a quick accuracy check (position RMSE after aligning
// position and yaw at the first state; the reported ATE comes from hdvio_eval).
#include <ceres/types.h>
#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/asl.h"

DEFINE_string(dataset, "", "ASL folder with landmark tracks (hdvio_sim output)");
DEFINE_string(config, "", "Experiment YAML (method, backend, run sections)");
DEFINE_string(method, "", "Override the config's method (vio | vimo | vid | hdvio)");
DEFINE_bool(gt_init, false, "Start from the ground-truth state instead of the static guess");
DEFINE_string(linear_solver, "", "Override backend.linear_solver");
DEFINE_int32(max_iterations, 0, "Override backend.max_iterations (> 0)");
DEFINE_string(landmarks_first, "", "Override backend.landmarks_first (true | false)");
DEFINE_string(frames_csv, "", "Also write one row per frame (timings, window, solver) to this CSV");

namespace hdvio {
namespace {

struct Stats {
  std::size_t n = 0;
  double median = 0, p90 = 0, max = 0, mean = 0;
};

Stats statsOf(std::vector<double> v) {
  Stats s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p90 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.9 * v.size())) - 1)];
  s.max = v.back();
  for (double x : v) s.mean += x / static_cast<double>(v.size());
  return s;
}

void print(const char* what, const Stats& s, const char* unit) {
  std::printf("%-34s n=%-5zu median %7.2f  p90 %7.2f  max %7.2f  mean %7.2f %s\n", what, s.n,
              s.median, s.p90, s.max, s.mean, unit);
}

double yawOf(const Quat& q) {
  const Vec3 x = q * Vec3::UnitX();
  return std::atan2(x.y(), x.x());
}

int run() {
  if (FLAGS_dataset.empty() || FLAGS_config.empty())
    throw InputError("", 0, "--dataset and --config are required");
  const ConfigReader config = ConfigReader::fromFile(FLAGS_config);
  std::string method_name;
  config.read("method", &method_name);
  if (!FLAGS_method.empty()) method_name = FLAGS_method;
  VioMethod method;
  try {
    method = parseVioMethod(method_name);
  } catch (const std::invalid_argument& e) {
    throw InputError(FLAGS_config, 0, e.what());
  }
  VioBackendOptions options = loadVioBackendOptions(config.optionalSection("backend"), method);
  if (!FLAGS_linear_solver.empty() &&
      !ceres::StringToLinearSolverType(FLAGS_linear_solver, &options.linear_solver))
    throw InputError("", 0, "--linear_solver: unknown solver '" + FLAGS_linear_solver + "'");
  if (FLAGS_max_iterations > 0) options.max_iterations = FLAGS_max_iterations;
  if (!FLAGS_landmarks_first.empty()) options.landmarks_first = FLAGS_landmarks_first == "true";
  VioRunOptions run;
  const ConfigReader r = config.optionalSection("run");
  r.readOptional("init_from_groundtruth", &run.init_from_groundtruth);
  r.readInRange("pixel_noise_sigma", &run.pixel_noise_sigma, 0.0, 100.0);
  int seed = static_cast<int>(run.seed);
  r.readInRange("seed", &seed, 0, 1 << 30);
  run.seed = static_cast<std::uint32_t>(seed);
  if (FLAGS_gt_init) run.init_from_groundtruth = true;

  io::ReadOptions read;
  read.check_images_exist = false;
  const Sequence seq = io::readAsl(FLAGS_dataset, read);
  const VioRunOutput out = runVioOnTracks(seq, options, run);

  if (!FLAGS_frames_csv.empty()) {
    const std::string tmp = FLAGS_frames_csv + ".tmp";  // written whole, then renamed
    {
      std::ofstream csv(tmp);
      csv << "t_ns,keyframe,cpu_ms,marginalization_ms,solve_ms,iterations,landmarks,outliers\n";
      for (const FrameResult& f : out.frames)
        csv << f.state.t << ',' << f.keyframe << ',' << 1e3 * f.cpu_time_s << ','
            << 1e3 * f.marginalization_cpu_s << ',' << 1e3 * f.solve_time_s << ','
            << f.solver_iterations << ',' << f.landmarks_in_window << ',' << f.outliers_removed
            << '\n';
      if (!csv.flush()) throw InputError(FLAGS_frames_csv, 0, "cannot write");
    }
    if (std::rename(tmp.c_str(), FLAGS_frames_csv.c_str()) != 0)
      throw InputError(FLAGS_frames_csv, 0, "cannot write");
  }
  std::vector<double> all, key, nonkey, marg, solver, landmarks, iterations;
  for (const FrameResult& f : out.frames) {
    if (f.cpu_time_s <= 0.0) continue;  // the initialization frame
    all.push_back(1e3 * f.cpu_time_s);
    (f.keyframe ? key : nonkey).push_back(1e3 * f.cpu_time_s);
    marg.push_back(1e3 * f.marginalization_cpu_s);
    solver.push_back(1e3 * f.solve_time_s);
    landmarks.push_back(f.landmarks_in_window);
    iterations.push_back(f.solver_iterations);
  }
  std::printf("%s on %s: %zu frames, %s init, linear solver %s, max %d iterations\n",
              toString(method).c_str(), seq.name.c_str(), all.size(),
              run.init_from_groundtruth ? "ground-truth" : "static", ceres::LinearSolverTypeToString(options.linear_solver),
              options.max_iterations);
  print("per frame, CPU", statsOf(all), "ms");
  print("per keyframe update, CPU", statsOf(key), "ms");
  print("per non-keyframe update, CPU", statsOf(nonkey), "ms");
  print("  window maintenance (marg.), CPU", statsOf(marg), "ms");
  print("  last solve (Ceres total)", statsOf(solver), "ms");
  print("landmarks in window", statsOf(landmarks), "");
  print("solver iterations (last solve)", statsOf(iterations), "");

  // Quick accuracy check: align position and yaw at the first state (the estimator's gauge).
  if (!seq.groundtruth.empty() && !out.states.empty()) {
    const NavState& s0 = out.states.front();
    const NavState g0 = groundTruthState(seq, s0.t);
    const Quat dq(Eigen::AngleAxisd(yawOf(g0.T_WB.q) - yawOf(s0.T_WB.q), Vec3::UnitZ()));
    double se = 0.0;
    for (const NavState& s : out.states) {
      const Vec3 p = dq * (s.T_WB.p - s0.T_WB.p) + g0.T_WB.p;
      se += (p - groundTruthState(seq, s.t).T_WB.p).squaredNorm();
    }
    std::printf("position rmse (first-state aligned): %.4f m\n", std::sqrt(se / out.states.size()));
  }
  return 0;
}

}  // namespace
}  // namespace hdvio

int main(int argc, char** argv) {
  gflags::SetUsageMessage("hdvio_backend_bench --dataset <ASL folder> --config <experiment.yaml>");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return hdvio::runTool(hdvio::run);
}
