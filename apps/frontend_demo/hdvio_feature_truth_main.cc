// hdvio_feature_truth: the visual pipeline (frontend + backend, as hdvio_run) on a flight rendered
// by hdvio_sim, with every frontend observation checked against the simulator's truth. A
// landmark's true 3-D point is where the ray of its first observation, from the true camera
// pose, meets the scene (room box or gate); every later observation is compared with that
// point's projection at the true pose of its image. Prints where the visual error enters:
// feature position error (by pyramid level and track age), track lengths, landmarks and
// observations per window, outliers, new landmarks' depth error.
#include <gflags/gflags.h>
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/eval/alignment.h"
#include "hdvio/io/asl.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/run/visual_frontend_config.h"
#include "hdvio/sim/simulator.h"
#include "feature_truth.h"

DEFINE_string(config, "", "experiment YAML of a visual method on images (as for hdvio_run)");
DEFINE_string(dataset, "", "folder written by hdvio_sim (mav0/ and sim_config.yaml)");
DEFINE_string(observations, "", "optional CSV of every checked observation");

namespace hdvio {
namespace {

struct Experiment {
  VioBackendOptions backend;
  VioRunOptions run;
  VisualFrontendConfig frontend;
};

// The keys hdvio_run's visual pipeline reads (apps/run/src/visual_pipeline.cc); the rest is an error.
Experiment loadExperiment(const std::string& path) {
  const ConfigReader cfg = ConfigReader::fromFile(path);
  std::string method;
  cfg.readChoice("method", &method, {"vio", "vimo", "vid", "hdvio"}, true);
  Experiment e;
  e.backend = loadVioBackendOptions(cfg.optionalSection("backend"), parseVioMethod(method));
  const ConfigReader r = cfg.optionalSection("run");
  r.readOptional("init_from_groundtruth", &e.run.init_from_groundtruth);
  r.readOptional("visual_inertial_init", &e.run.visual_inertial_init);
  r.readInRange("vi_init_window_s", &e.run.vi_init_window_s, 0.5, 10.0);
  r.readInRange("vi_init_timeout_s", &e.run.vi_init_timeout_s, 0.0, 60.0);
  r.readInRange("image_noise_sigma", &e.run.image_noise_sigma, 0.0, 50.0);
  int seed = static_cast<int>(e.run.seed);
  r.readInRange("seed", &seed, 0, 1 << 30);
  e.run.seed = static_cast<std::uint32_t>(seed);
  r.finish();
  e.frontend = run::loadVisualFrontendConfig(cfg.optionalSection("frontend"));
  if (e.frontend.source == ObservationSource::kTracks)
    throw InputError(path, 0, "frontend.source: tracks has no frontend to check; use images");
  e.frontend.source = ObservationSource::kImages;
  cfg.finish();
  return e;
}

int runMain() {
  cv::setNumThreads(1);
  if (FLAGS_config.empty() || FLAGS_dataset.empty())
    throw InputError("", 0, "usage: hdvio_feature_truth --config <yaml> --dataset <hdvio_sim folder>");
  const Experiment e = loadExperiment(FLAGS_config);
  const std::string sim_yaml = (std::filesystem::path(FLAGS_dataset) / "sim_config.yaml").string();
  if (!std::filesystem::exists(sim_yaml))
    throw InputError(sim_yaml, 0, "missing: the dataset must be a folder written by hdvio_sim");
  const sim::Simulator simulator(sim::loadSimConfig(ConfigReader::fromFile(sim_yaml)));
  const Sequence seq = io::readAsl(FLAGS_dataset);
  if (!seq.camera) throw InputError(FLAGS_dataset, 0, "sequence has no camera");
  if (seq.groundtruth.empty()) throw InputError(FLAGS_dataset, 0, "sequence has no ground truth");

  FeatureTruthChecker checker(*simulator.scene(), CameraModel::fromCalibration(*seq.camera),
                              seq.camera->T_BS, [&seq](Timestamp t) { return groundTruthState(seq, t).T_WB; });
  const ImageRunOutput out = runVioOnImages(seq, e.backend, e.run, e.frontend, nullptr, true, {},
                                            [&](const ImageStep& step) { checker.add(step); });
  const FeatureTruthSummary s = checker.summary();
  std::printf("scene: %zu gates\n%s", simulator.scene()->gates().size(), formatSummary(s, out).c_str());
  // Position ATE over the states (one per processed image), posyaw-aligned as hdvio_run reports.
  std::vector<Vec3> est, ref;
  for (const NavState& x : out.vio.states) {
    est.push_back(x.T_WB.p);
    ref.push_back(groundTruthState(seq, x.t).T_WB.p);
  }
  const eval::SimilarityTransform T = eval::positionYawAlignment(est, ref);
  double sum2 = 0;
  for (size_t i = 0; i < est.size(); ++i) sum2 += (T.apply(est[i]) - ref[i]).squaredNorm();
  std::printf("ATE_T posyaw %.4f m over %zu states\n", std::sqrt(sum2 / static_cast<double>(est.size())),
              est.size());
  // Where the error is made: the unaligned error (the run starts at the true state) in the
  // first 10 s (the start of motion) and after.
  double early2 = 0, late2 = 0, early_max = 0, late_max = 0;
  int early = 0, late = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    const double e = (est[i] - ref[i]).norm();
    if (toSeconds(out.vio.states[i].t - out.vio.states.front().t) < 10.0) {
      early2 += e * e, early_max = std::max(early_max, e), ++early;
    } else {
      late2 += e * e, late_max = std::max(late_max, e), ++late;
    }
  }
  std::printf("position error without alignment [m]: first 10 s rms %.4f max %.4f; after rms %.4f max %.4f\n",
              early ? std::sqrt(early2 / early) : 0.0, early_max, late ? std::sqrt(late2 / late) : 0.0,
              late_max);
  if (!FLAGS_observations.empty()) checker.writeObservations(FLAGS_observations);
  return 0;
}

}  // namespace
}  // namespace hdvio

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_feature_truth --config <experiment.yaml> --dataset <hdvio_sim folder> [--observations out.csv]\n"
      "runs the visual pipeline on a rendered flight and checks every frontend observation against\n"
      "the simulator's true projection of the landmark's first-observation ray\n"
      "example: hdvio_feature_truth --config config/experiments/sim_images_vio_gt.yaml --dataset /tmp/seq/random_v10");
  return hdvio::runTool(hdvio::runMain);
}
