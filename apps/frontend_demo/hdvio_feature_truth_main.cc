// hdvio_feature_truth: the visual pipeline (frontend + backend, as hdvio_run) on a flight with
// ground truth, every frontend observation checked against the truth. On a flight rendered by
// hdvio_sim a landmark's true 3-D point is where the ray of its first observation, from the true
// camera pose, meets the scene (room box or gate), and every later observation is compared with
// that point's projection at the true pose of its image. On any other flight (another
// simulator's, a real one) the point is triangulated from the whole track at the true poses. Prints where the visual error enters:
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
#include "hdvio/pipeline/visual_frontend_config_loader.h"
#include "hdvio/sim/simulator.h"
#include "feature_truth.h"
#include "track_geometry.h"

DEFINE_string(config, "", "experiment YAML of a visual method on images (as for hdvio_run)");
DEFINE_string(dataset, "", "ASL folder with cam0 and ground truth (an hdvio_sim folder: checked against its scene)");
DEFINE_string(observations, "", "optional CSV of every checked observation");

namespace hdvio {
namespace {

struct Experiment {
  ConfigReader backend_cfg;
  VioBackendOptions backend;
  VioRunOptions run;
  VisualFrontendConfig frontend;
};

// The keys hdvio_run's visual pipeline reads (apps/run/src/visual_pipeline.cc); the rest is an error.
Experiment loadExperiment(const std::string& path) {
  const ConfigReader cfg = ConfigReader::fromFile(path);
  std::string method;
  cfg.readChoice("method", &method, {"vio", "vimo", "vid", "hdvio"}, true);
  Experiment e{cfg.optionalSection("backend"), {}, {}, {}};
  e.backend = loadVioBackendOptions(e.backend_cfg, parseVioMethod(method));
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
  e.frontend = loadVisualFrontendConfig(cfg.optionalSection("frontend"));
  if (e.frontend.source == ObservationSource::kTracks)
    throw InputError(path, 0, "frontend.source: tracks has no frontend to check; use images");
  e.frontend.source = ObservationSource::kImages;
  cfg.finish();
  return e;
}

int runMain() {
  cv::setNumThreads(1);
  if (FLAGS_config.empty() || FLAGS_dataset.empty())
    throw InputError("", 0, "usage: hdvio_feature_truth --config <yaml> --dataset <ASL folder>");
  Experiment e = loadExperiment(FLAGS_config);
  const Sequence seq = io::readAsl(FLAGS_dataset);
  if (!seq.camera) throw InputError(FLAGS_dataset, 0, "sequence has no camera");
  if (seq.groundtruth.empty()) throw InputError(FLAGS_dataset, 0, "sequence has no ground truth");
  if (seq.imu_calibration) adoptImuNoise(*seq.imu_calibration, e.backend_cfg, &e.backend);
  const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
  const auto truth = [&seq](Timestamp t) { return groundTruthState(seq, t).T_WB; };
  // A flight of hdvio_sim: its scene gives each landmark's true point. Any other flight: the
  // point triangulated from the track at the true poses (track_geometry.h).
  const std::string sim_yaml = (std::filesystem::path(FLAGS_dataset) / "sim_config.yaml").string();
  ImageRunOutput out;
  if (std::filesystem::exists(sim_yaml)) {
    const sim::Simulator simulator(sim::loadSimConfig(ConfigReader::fromFile(sim_yaml)));
    FeatureTruthChecker checker(*simulator.scene(), camera, seq.camera->T_BS, truth);
    out = runVioOnImages(seq, e.backend, e.run, e.frontend, nullptr, true, {},
                         [&](const ImageStep& step) { checker.add(step); });
    std::printf("scene: %zu gates\n%s", simulator.scene()->gates().size(),
                formatSummary(checker.summary(), out).c_str());
    if (!FLAGS_observations.empty()) checker.writeObservations(FLAGS_observations);
  } else {
    if (!FLAGS_observations.empty())
      throw InputError(FLAGS_dataset, 0, "--observations needs a folder written by hdvio_sim (its scene)");
    TrackGeometryChecker checker(camera, seq.camera->T_BS, truth);
    out = runVioOnImages(seq, e.backend, e.run, e.frontend, nullptr, true, {},
                         [&](const ImageStep& step) { checker.add(step); });
    std::printf("no scene (not an hdvio_sim folder): tracks triangulated at the true poses\n%s",
                formatGeometrySummary(checker.summary(), out, checker.landmarksInThreeImages()).c_str());
  }
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
  return 0;
}

}  // namespace
}  // namespace hdvio

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_feature_truth --config <experiment.yaml> --dataset <ASL folder> [--observations out.csv]\n"
      "runs the visual pipeline on a flight with ground truth and checks every frontend observation\n"
      "against the truth: hdvio_sim's scene, else the track triangulated at the true poses\n"
      "example: hdvio_feature_truth --config config/experiments/sim_images_vio_gt.yaml --dataset /tmp/seq/random_v10");
  return hdvio::runTool(hdvio::runMain);
}
