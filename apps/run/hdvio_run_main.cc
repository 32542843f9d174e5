// hdvio_run: one experiment (YAML) on one sequence (ASL folder or supported flight).
//   hdvio_run --config config/experiments/vio.yaml --dataset <folder> --out <dir>
// Visual methods currently run the backend on the sequence's ground-truth landmark tracks
// (simulated sequences); see docs/running.md.
#include <gflags/gflags.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <cstdio>

#include "hdvio/backend/vio_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/learned/residual_force_provider.h"
#include "hdvio/run/result_writer.h"

DEFINE_string(config, "", "experiment YAML (method, backend, run sections)");
DEFINE_string(dataset, "", "ASL folder or supported flight (Blackbird, DIDO, NeuroBEM)");
DEFINE_string(out, "", "output folder (created; an earlier result there is replaced)");

namespace hdvio {
namespace {

int runMain() {
  if (FLAGS_config.empty() || FLAGS_dataset.empty() || FLAGS_out.empty())
    throw InputError("", 0, "usage: hdvio_run --config <yaml> --dataset <path> --out <dir>");
  run::checkOutputFolder(FLAGS_out);
  const ConfigReader cfg = ConfigReader::fromFile(FLAGS_config);
  std::string method_name;
  cfg.readChoice("method", &method_name, {"vio", "vimo", "vid", "hdvio"}, true);
  const VioMethod method = parseVioMethod(method_name);
  const VioBackendOptions options = loadVioBackendOptions(cfg.optionalSection("backend"), method);
  VioRunOptions run;
  {
    const ConfigReader r = cfg.optionalSection("run");
    r.readOptional("init_from_groundtruth", &run.init_from_groundtruth);
    r.readInRange("pixel_noise_sigma", &run.pixel_noise_sigma, 0.0, 100.0);
    int seed = static_cast<int>(run.seed);
    r.readInRange("seed", &seed, 0, 1 << 30);
    run.seed = static_cast<std::uint32_t>(seed);
    r.finish();
  }
  // hdvio: the learned residual force (residual_force: {type: tcn, weights: ...}); zero if absent.
  std::shared_ptr<learned::ResidualForceProvider> provider;
  if (cfg.has("residual_force")) {
    if (method != VioMethod::kHdvio)
      throw InputError(FLAGS_config, 0, "residual_force is only used by method hdvio");
    provider = learned::makeResidualForceProvider(
        cfg.section("residual_force"),
        std::filesystem::path(FLAGS_config).parent_path().string());
  }
  cfg.finish();

  const Sequence seq = io::readSequence(FLAGS_dataset);
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  ResidualForceSource residual_force;
  if (provider) {
    residual_force = [provider, &seq, &thrust](Timestamp t_i, Timestamp t_j, const Vec3& gyro_bias) {
      const Timestamp from = t_i - fromSeconds(provider->historySeconds());
      const auto inputs = learned::makeDynamicsInputs(seq.imu, thrust, from, t_j);
      auto forces = std::make_shared<const std::vector<learned::ResidualForce>>(
          provider->residualForces(inputs, t_i, t_j, gyro_bias));
      return ResidualForceFn([forces](Timestamp t) { return learned::residualForceAt(*forces, t); });
    };
  }
  if (seq.landmark_observations.empty())
    throw InputError(FLAGS_dataset, 0,
                     "no landmark tracks (landmarks0/): this build runs visual methods on simulated "
                     "tracks only; the image frontend is not connected yet");
  std::fprintf(stderr, "hdvio_run: %s on %s (%zu IMU samples, %zu frames)\n", method_name.c_str(),
               seq.name.c_str(), seq.imu.size(), seq.images.size());
  const VioRunOutput out = runVioOnTracks(seq, options, run, residual_force);

  run::RunResults results;
  results.states = out.states;
  results.has_force = usesDynamics(method);
  results.effective_config = cfg.effectiveYaml();
  for (const auto& f : out.frames)
    results.timing.push_back({f.state.t, 1e3 * f.solve_time_s, f.solver_iterations,
                              f.landmarks_in_window, f.observations_used, f.keyframe});
  run::writeResults(results, FLAGS_out);
  std::fprintf(stderr, "hdvio_run: %zu states, backend %.2f s (%.1f ms/frame), results in %s\n",
               out.states.size(), out.backend_time_s,
               1e3 * out.backend_time_s / std::max<std::size_t>(1, out.states.size()),
               FLAGS_out.c_str());
  return 0;
}

}  // namespace
}  // namespace hdvio

int main(int argc, char** argv) {
  gflags::SetUsageMessage("hdvio_run --config <yaml> --dataset <path> --out <dir>");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return hdvio::runTool(hdvio::runMain);
}
