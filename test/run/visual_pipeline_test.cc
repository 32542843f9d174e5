// The image pipeline of the visual methods: the semi-direct frontend feeding the sliding-window
// backend on a small rendered flight and on the EuRoC excerpt, estimates checked against
// ground truth; missing images are a clear error.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "../common/run_command.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/eval/alignment.h"
#include "hdvio/io/asl.h"
#include "hdvio/run/noisy_image_copy.h"
#include "hdvio/run/result_writer.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

using Outcome = test::CommandOutcome;
Outcome runTool(const std::string& args) {
  return test::runCommand(std::string(HDVIO_RUN_BINARY) + " " + args);
}

// RMS and maximum position error of the estimates against the (interpolated) ground truth,
// after the first `skip_s` seconds; no alignment: the runs start from the true state.
struct PositionError {
  double rms = 0.0, max = 0.0;
  int n = 0;
};
PositionError positionError(const Sequence& seq, const std::vector<NavState>& states) {
  PositionError e;
  double sum = 0.0;
  for (const NavState& s : states) {
    const Vec3 d = s.T_WB.p - groundTruthState(seq, s.t).T_WB.p;
    sum += d.squaredNorm();
    e.max = std::max(e.max, d.norm());
    ++e.n;
  }
  e.rms = e.n > 0 ? std::sqrt(sum / e.n) : 0.0;
  return e;
}

// Position RMS after the rpg posyaw alignment over all states: a visual-inertial or static start
// has its own gauge (first body at the origin, yaw 0).
double alignedPositionRms(const Sequence& seq, const std::vector<NavState>& states) {
  std::vector<Vec3> est, ref;
  for (const NavState& s : states) {
    est.push_back(s.T_WB.p);
    ref.push_back(groundTruthState(seq, s.t).T_WB.p);
  }
  const eval::SimilarityTransform T = eval::positionYawAlignment(est, ref);
  double sum = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) sum += (T.apply(est[i]) - ref[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(est.size()));
}

// Errors of the visual-inertial initialization's window states against ground truth (gauge
// free): scale from the summed distances to the first state, gravity and velocity in the body.
struct StartErrors {
  double scale = 0.0;        // abs(1 - estimated / true)
  double gravity_deg = 0.0;  // largest angle between estimated and true gravity (body frame)
  double velocity = 0.0;     // largest body-frame velocity error, m/s
};
StartErrors startErrors(const Sequence& seq, const std::vector<NavState>& states) {
  StartErrors e;
  double est_len = 0.0, true_len = 0.0;
  const NavState gt0 = groundTruthState(seq, states.front().t);
  for (const NavState& s : states) {
    const NavState gt = groundTruthState(seq, s.t);
    est_len += (s.T_WB.p - states.front().T_WB.p).norm();
    true_len += (gt.T_WB.p - gt0.T_WB.p).norm();
    const Vec3 g_est = s.T_WB.R().transpose() * Vec3::UnitZ();
    const Vec3 g_true = gt.T_WB.R().transpose() * Vec3::UnitZ();
    e.gravity_deg = std::max(e.gravity_deg, std::acos(std::clamp(g_est.dot(g_true), -1.0, 1.0)) *
                                                180.0 / M_PI);
    e.velocity = std::max(e.velocity, (s.T_WB.R().transpose() * s.v_W -
                                       gt.T_WB.R().transpose() * gt.v_W).norm());
  }
  e.scale = std::abs(1.0 - est_len / true_len);
  return e;
}

VisualFrontendConfig smallImageFrontend() {
  VisualFrontendConfig c;
  c.options.detector.cell_size = 16;  // 320x240: the default 32 px grid leaves too few corners
  return c;
}

sim::SimConfig simConfig(const std::string& name) {
  return sim::loadSimConfig(
      ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/" + name + ".yaml"));
}

// Renders the flight into dir/seq (images only, tracks removed) and reads it back.
Sequence renderImagesOnly(const sim::SimConfig& config, const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const sim::Simulator simulator(config);
  sim::SimulationResult result = simulator.simulate();
  simulator.renderImages(&result, (dir / "rendered").string());
  result.sequence.landmark_observations.clear();  // images only
  io::writeAsl(result.sequence, (dir / "seq").string());
  fs::remove_all(dir / "rendered");
  return io::readAsl((dir / "seq").string());
}

class VisualPipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hdvio_visual_pipeline_test_" + std::to_string(getpid()));
    sequence_ = new Sequence(renderImagesOnly(simConfig("ci_images"), dir_));
  }
  static void TearDownTestSuite() {
    delete sequence_;
    fs::remove_all(dir_);
  }
  static fs::path dir_;
  static Sequence* sequence_;
};
fs::path VisualPipeline::dir_;
Sequence* VisualPipeline::sequence_ = nullptr;

TEST_F(VisualPipeline, VioOnRenderedImagesFollowsGroundTruth) {
  VioRunOptions run;
  run.init_from_groundtruth = true;
  const auto out = runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVio), run,
                                       smallImageFrontend(), nullptr, /*log=*/false);
  ASSERT_EQ(out.images.size(), sequence_->images.size());
  EXPECT_GE(out.vio.states.size(), sequence_->images.size() - 1);
  EXPECT_LE(out.lost_images, 2);
  EXPECT_EQ(out.reinitializations, 0);
  const PositionError e = positionError(*sequence_, out.vio.states);
  const double path = 1.5 * (4.0 - 0.5);  // about 5 m flown
  EXPECT_LT(e.rms, 0.05) << "over " << e.n << " states, " << path << " m of path";
  EXPECT_LT(e.max, 0.10);
}

TEST_F(VisualPipeline, VimoOnRenderedImagesFollowsGroundTruth) {
  VioRunOptions run;
  run.init_from_groundtruth = true;
  const auto out = runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVimo),
                                       run, smallImageFrontend(), nullptr, /*log=*/false);
  const PositionError e = positionError(*sequence_, out.vio.states);
  EXPECT_LT(e.rms, 0.05);
  EXPECT_LT(e.max, 0.10);
}

TEST_F(VisualPipeline, CoveredCameraFallsBackToImuAndRecovers) {
  // One second of black images in the middle: the backend must carry on with the IMU, the
  // frontend must re-initialize, and the estimate must stay close to the truth.
  Sequence seq = *sequence_;
  const fs::path black = dir_ / "black.png";
  cv::Mat dark(seq.camera->height, seq.camera->width, CV_8UC1, cv::Scalar(0));
  ASSERT_TRUE(cv::imwrite(black.string(), dark));
  const Timestamp t0 = seq.images.front().t;
  int covered = 0;
  for (auto& img : seq.images)
    if (img.t - t0 > fromSeconds(2.0) && img.t - t0 <= fromSeconds(2.5)) {
      img.path = black.string();
      ++covered;
    }
  ASSERT_GT(covered, 5);
  VioRunOptions run;
  run.init_from_groundtruth = true;
  const auto out = runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio), run,
                                       smallImageFrontend(), nullptr, /*log=*/false);
  EXPECT_GE(out.lost_images, covered);
  EXPECT_LE(out.lost_images, covered + 4);
  EXPECT_GE(out.reinitializations, 1);
  EXPECT_FALSE(out.images.back().stage == frontend::TrackingStage::kRelocalizing);
  EXPECT_TRUE(out.images.back().used_by_backend);
  const PositionError e = positionError(seq, out.vio.states);
  EXPECT_LT(e.max, 0.3);
}

TEST(TimeQuantiles, NearestRankOfMeasuredTimes) {
  std::vector<double> ms;
  for (int i = 20; i >= 1; --i) ms.push_back(i);  // 1 .. 20 ms, unsorted
  const run::TimeQuantiles q = run::timeQuantiles(ms);
  EXPECT_DOUBLE_EQ(q.mean, 10.5);
  EXPECT_DOUBLE_EQ(q.p50, 10.0);  // rank ceil(0.5 * 20) = 10
  EXPECT_DOUBLE_EQ(q.p90, 18.0);  // rank 18
  EXPECT_DOUBLE_EQ(q.max, 20.0);
  EXPECT_DOUBLE_EQ(run::timeQuantiles({7.0}).p90, 7.0);
  EXPECT_TRUE(std::isnan(run::timeQuantiles({}).mean));
}

TEST_F(VisualPipeline, WritesTheTimeOfEveryImage) {
  const fs::path cfg = dir_ / "timed.yaml";
  std::ofstream(cfg) << "method: vio\nrun: {init_from_groundtruth: true}\nfrontend:\n"
                        "  source: images\n  detector: {cell_size: 16}\n";
  const fs::path out = dir_ / "timed";
  const Outcome o = runTool("--config " + cfg.string() + " --dataset " + (dir_ / "seq").string() +
                            " --out " + out.string() + " --evaluate=false");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  // One row per image the frontend saw (all but those before the ground-truth start).
  const std::vector<double> ms = run::readImageProcessingMs((out / "timing_images.csv").string());
  EXPECT_GE(ms.size() + 1, sequence_->images.size());
  EXPECT_LE(ms.size(), sequence_->images.size());
  for (double x : ms) EXPECT_GT(x, 0.0);
  std::ifstream stages(out / "timing_stages.csv");
  std::string line;
  std::getline(stages, line);
  EXPECT_EQ(line, "stage,total [s],calls,mean [ms],p50 [ms],p90 [ms],max [ms]");
  int timed = 0;
  double frontend_s = 0.0, parts_s = 0.0;
  std::set<std::string> parts;
  while (std::getline(stages, line)) {
    const std::string name = line.substr(0, line.find(','));
    const bool part = name.rfind("frontend/", 0) == 0;
    if (name != "frontend" && name != "backend" && !part) continue;
    double v[6];
    ASSERT_EQ(std::sscanf(line.c_str() + line.find(',') + 1, "%lf,%lf,%lf,%lf,%lf,%lf", &v[0],
                          &v[1], &v[2], &v[3], &v[4], &v[5]), 6) << line;
    EXPECT_EQ(static_cast<std::size_t>(v[1]), ms.size()) << line;
    EXPECT_LE(v[3], v[4]) << line;  // p50 <= p90 <= max
    EXPECT_LE(v[4], v[5]) << line;
    if (part) {
      parts.insert(name);
      parts_s += v[0];
    } else {
      ++timed;
    }
    if (name == "frontend") frontend_s = v[0];
  }
  EXPECT_EQ(timed, 2);
  // The frontend's parts: every one listed, each timed inside the frontend's own call (their
  // share of it is a wall-clock matter, not asserted: under load it moves).
  EXPECT_EQ(parts, (std::set<std::string>{"frontend/pyramid", "frontend/alignment",
                                          "frontend/reprojection", "frontend/optimization",
                                          "frontend/depth_filter", "frontend/keyframe"}));
  EXPECT_GT(parts_s, 0.0);
  EXPECT_LE(parts_s, frontend_s);
}

// run.duration_s runs the flight's first seconds only. The estimator is causal, so the cut run's
// trajectory must be the whole run's first lines byte for byte, ending at the cut.
TEST_F(VisualPipeline, RunDurationIsTheWholeRunsPrefix) {
  const auto run = [&](const std::string& tag, const std::string& extra) {
    const fs::path cfg = dir_ / (tag + ".yaml");
    std::ofstream(cfg) << "method: vio\nrun: {init_from_groundtruth: true" << extra
                       << "}\nfrontend:\n  source: images\n  detector: {cell_size: 16}\n";
    const fs::path out = dir_ / tag;
    const Outcome o = runTool("--config " + cfg.string() + " --dataset " +
                              (dir_ / "seq").string() + " --out " + out.string() +
                              " --evaluate=false");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    std::vector<std::string> lines;
    std::ifstream in(out / "stamped_traj_estimate.txt");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  };
  const std::vector<std::string> whole = run("whole", "");
  const std::vector<std::string> cut = run("cut", ", duration_s: 1.5");
  const double first = toSeconds(sequence_->images.front().t);
  ASSERT_GT(cut.size(), 10u);
  ASSERT_LT(cut.size() + 10, whole.size());
  for (std::size_t i = 0; i < cut.size(); ++i) ASSERT_EQ(cut[i], whole[i]) << "line " << i;
  const double last = std::stod(cut.back());
  EXPECT_LE(last, first + 1.5 + 1e-9);
  EXPECT_GT(last, first + 1.5 - 1.0 / sequence_->camera->rate_hz - 1e-9);
  EXPECT_GT(std::stod(whole[cut.size()]), first + 1.5);
}

// A peer compared over noise seeds must see the pixels hdvio's seeded run sees: on the copy
// written by writeNoisyImageCopy (hdvio_image_noise) without added noise, hdvio_run must write
// the seeded run's trajectory byte for byte; another seed's copy must give another trajectory.
TEST_F(VisualPipeline, NoisyImageCopyHoldsTheSeededRunsPixels) {
  const auto runOn = [&](const std::string& tag, const fs::path& dataset, const std::string& extra) {
    const fs::path cfg = dir_ / (tag + ".yaml");
    std::ofstream(cfg) << "method: vio\nrun: {init_from_groundtruth: true, duration_s: 1.5" << extra
                       << "}\nfrontend:\n  source: images\n  detector: {cell_size: 16}\n";
    const fs::path out = dir_ / tag;
    const Outcome o = runTool("--config " + cfg.string() + " --dataset " + dataset.string() +
                              " --out " + out.string() + " --evaluate=false");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    std::ifstream in(out / "stamped_traj_estimate.txt");
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const fs::path copy2 = dir_ / "noisy_seed2", copy3 = dir_ / "noisy_seed3";
  run::writeNoisyImageCopy((dir_ / "seq").string(), 3.0, 2, copy2.string());
  run::writeNoisyImageCopy((dir_ / "seq").string(), 3.0, 3, copy3.string());
  EXPECT_TRUE(fs::is_symlink(copy2 / "mav0" / "imu0"));
  EXPECT_THROW(run::writeNoisyImageCopy((dir_ / "seq").string(), 3.0, 2, copy2.string()),
               InputError);  // never overwrites
  // A corrupt image is an error naming it; nothing is left behind, not even the partial copy.
  const fs::path bad = dir_ / "bad_seq";
  fs::copy(dir_ / "seq", bad, fs::copy_options::recursive);
  std::ofstream(bad / "mav0" / "cam0" / "data" /
                fs::path(sequence_->images[5].path).filename(), std::ios::trunc) << "not a png";
  try {
    run::writeNoisyImageCopy(bad.string(), 3.0, 2, (dir_ / "bad_copy").string());
    ADD_FAILURE() << "no error for a corrupt image";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("data.csv"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "bad_copy"));
  EXPECT_FALSE(fs::exists(dir_ / "bad_copy.partial"));
  const std::string seeded = runOn("seeded2", dir_ / "seq", ", image_noise_sigma: 3, seed: 2");
  ASSERT_GT(seeded.size(), 100u);
  EXPECT_EQ(runOn("copy2", copy2, ""), seeded);
  EXPECT_NE(runOn("copy3", copy3, ""), seeded);
  EXPECT_NE(runOn("clean", dir_ / "seq", ""), seeded);
}

TEST_F(VisualPipeline, MissingImagesAreClearErrors) {
  const fs::path copy = dir_ / "missing_image";
  fs::copy(dir_ / "seq", copy, fs::copy_options::recursive);
  const fs::path data = copy / "mav0" / "cam0" / "data";
  fs::path victim;
  for (const auto& entry : fs::directory_iterator(data)) victim = entry.path();
  ASSERT_FALSE(victim.empty());
  fs::remove(victim);
  const fs::path cfg = dir_ / "images.yaml";
  std::ofstream(cfg) << "method: vio\nrun: {init_from_groundtruth: true}\nfrontend:\n"
                        "  source: images\n  detector: {cell_size: 16}\n";
  Outcome o = runTool("--config " + cfg.string() + " --dataset " + copy.string() + " --out " +
                      (dir_ / "o1").string());
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_NE(o.output.find("image file does not exist: " + victim.string()), std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o1"));

  // No images at all (and no landmark tracks): the method cannot run.
  const fs::path blind = dir_ / "no_images";
  fs::copy(dir_ / "seq", blind, fs::copy_options::recursive);
  fs::remove_all(blind / "mav0" / "cam0" / "data");
  fs::remove(blind / "mav0" / "cam0" / "data.csv");
  o = runTool("--config " + cfg.string() + " --dataset " + blind.string() + " --out " +
              (dir_ / "o2").string());
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o2"));

  // A typo in the frontend section is caught before any data is read.
  const fs::path typo = dir_ / "typo.yaml";
  std::ofstream(typo) << "method: vio\nfrontend:\n  source: images\n  max_feature: 100\n";
  o = runTool("--config " + typo.string() + " --dataset " + blind.string() + " --out " +
              (dir_ / "o3").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("frontend.max_feature"), std::string::npos) << o.output;
}

TEST_F(VisualPipeline, DefaultStartOnImagesIsVisualInertial) {
  // ci_images ramps up from rest over its first second, with yaw oscillating: the IMU is not
  // still, so the default start waits for the visual-inertial initialization on KLT tracks.
  const auto out = runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVio),
                                       VioRunOptions(), smallImageFrontend(), nullptr,
                                       /*log=*/false);
  ASSERT_EQ(out.vio.start, StartKind::kVisualInertial) << out.vio.vi_init.reason;
  EXPECT_TRUE(out.vio.visual_inertial_start);
  EXPECT_GT(out.init_images, 30);  // a ~2 s window of 20 Hz images went to the KLT tracker
  EXPECT_EQ(out.init_images + out.images.size(), sequence_->images.size() + 1);
  // Measured: scale 4.7 %, gravity 0.35 deg, velocity 0.055 m/s, position rms 0.070 m (the
  // window includes the ramp; docs/vi_initialization.md).
  const StartErrors e = startErrors(*sequence_, out.vio.vi_init.states);
  EXPECT_LT(e.scale, 0.07);
  EXPECT_LT(e.gravity_deg, 2.0);
  EXPECT_LT(e.velocity, 0.15);
  EXPECT_LE(out.lost_images, 2);
  const double rms = alignedPositionRms(*sequence_, out.vio.states);
  EXPECT_LT(rms, 0.1);
  std::printf("VI start (ramp) after %d attempts: scale %.2f %%, gravity %.2f deg, velocity "
              "%.3f m/s, position rms %.4f m\n",
              out.vio.vi_init_attempts, 100 * e.scale, e.gravity_deg, e.velocity, rms);
}

// Already flying at the first sample (config/sim/ci_images_moving.yaml: the circle at 1.5 m/s
// without the ramp, 6 s): a static start guesses zero velocity and a wrong tilt.
class VisualInertialStartOnImages : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hdvio_vi_start_test_" + std::to_string(getpid()));
    sequence_ = new Sequence(renderImagesOnly(simConfig("ci_images_moving"), dir_));
  }
  static void TearDownTestSuite() {
    delete sequence_;
    fs::remove_all(dir_);
  }
  static fs::path dir_;
  static Sequence* sequence_;
};
fs::path VisualInertialStartOnImages::dir_;
Sequence* VisualInertialStartOnImages::sequence_ = nullptr;

TEST_F(VisualInertialStartOnImages, MovingStartIsMetricAndGravityAligned) {
  const auto out = runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVio),
                                       VioRunOptions(), smallImageFrontend(), nullptr,
                                       /*log=*/false);
  ASSERT_EQ(out.vio.start, StartKind::kVisualInertial) << out.vio.vi_init.reason;
  const double t_init = secondsBetween(sequence_->images.front().t, out.vio.start_t);
  EXPECT_LT(t_init, 3.0) << "after " << out.vio.vi_init_attempts << " attempts";
  ASSERT_FALSE(out.vio.vi_init.states.empty());
  EXPECT_EQ(out.vio.vi_init.latest().t, out.vio.start_t);
  const StartErrors e = startErrors(*sequence_, out.vio.vi_init.states);
  EXPECT_LT(e.scale, 0.05);  // measured 2.1 %, 0.53 deg, 0.062 m/s, rms 0.025 m
  EXPECT_LT(e.gravity_deg, 2.0);
  EXPECT_LT(e.velocity, 0.15);
  // The frontend starts its map at that pose and the run stays metric to the end.
  EXPECT_EQ(out.reinitializations, 0);
  EXPECT_LE(out.lost_images, 2);
  EXPECT_TRUE(out.images.back().used_by_backend);
  const double rms = alignedPositionRms(*sequence_, out.vio.states);
  EXPECT_LT(rms, 0.05);
  std::printf("VI start after %.2f s (%d attempts): scale %.2f %%, gravity %.2f deg, velocity "
              "%.3f m/s, position rms %.4f m over %zu states\n",
              t_init, out.vio.vi_init_attempts, 100 * e.scale, e.gravity_deg, e.velocity, rms,
              out.vio.states.size());

  // What the VI start buys: the static start (zero velocity) on the same flight, same bounds.
  VioRunOptions static_start;
  static_start.visual_inertial_init = false;
  const auto guess = runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVio),
                                         static_start, smallImageFrontend(), nullptr,
                                         /*log=*/false);
  EXPECT_EQ(guess.vio.start, StartKind::kStatic);
  EXPECT_GT(alignedPositionRms(*sequence_, guess.vio.states), 5 * rms);
}

// The numbers of docs/vi_initialization.md ("On images"): default (VI) start against the static
// start on rendered flights; ~2 min. Run with --gtest_also_run_disabled_tests.
TEST(VisualInertialStartSweep, DISABLED_RenderedFlights) {
  sim::SimConfig lemniscate = simConfig("ci_images_moving");
  lemniscate.name = "lemniscate_images";
  lemniscate.seed = 3;
  lemniscate.duration = 10.0;
  lemniscate.trajectory.type = sim::TrajectoryType::kLemniscate;
  lemniscate.trajectory.max_speed = 3.0;
  lemniscate.trajectory.ramp_time = 1.0;
  lemniscate.trajectory.height_amplitude = 0.3;
  lemniscate.trajectory.extent = Vec3(2.0, 1.5, 0.3);
  lemniscate.yaw.amplitude = 20.0 * M_PI / 180.0;
  const std::vector<sim::SimConfig> flights = {simConfig("ci_images"),
                                               simConfig("ci_images_moving"), lemniscate,
                                               simConfig("demo")};
  const fs::path dir = fs::temp_directory_path() / ("hdvio_vi_sweep_" + std::to_string(getpid()));
  std::printf("| flight | start | t_init [s] | attempts | scale err %% | gravity [deg] | velocity "
              "[m/s] | init ms per image | ATE [m] (states) | static: start, ATE all / same "
              "span [m] |\n");
  for (const sim::SimConfig& flight : flights) {
    const Sequence seq = renderImagesOnly(flight, dir);
    VioRunOptions static_start;
    static_start.visual_inertial_init = false;
    const auto vi = runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio),
                                        VioRunOptions(), smallImageFrontend(), nullptr, false);
    const auto st = runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio),
                                        static_start, smallImageFrontend(), nullptr, false);
    StartErrors e;
    if (!vi.vio.vi_init.states.empty()) e = startErrors(seq, vi.vio.vi_init.states);
    std::vector<NavState> same_span;
    for (const NavState& s : st.vio.states)
      if (s.t >= vi.vio.start_t) same_span.push_back(s);
    std::printf("| %s | %s | %.2f | %d | %.2f | %.2f | %.3f | %.1f | %.4f (%zu) | %s, %.4f / %.4f "
                "|\n",
                flight.name.c_str(), toString(vi.vio.start).c_str(),
                secondsBetween(seq.images.front().t, vi.vio.start_t), vi.vio.vi_init_attempts,
                100 * e.scale, e.gravity_deg, e.velocity,
                1e3 * vi.init_time_s / std::max(1, vi.init_images),
                alignedPositionRms(seq, vi.vio.states), vi.vio.states.size(),
                toString(st.vio.start).c_str(), alignedPositionRms(seq, st.vio.states),
                alignedPositionRms(seq, same_span));
    std::fflush(stdout);
  }
  fs::remove_all(dir);
}

TEST(VisualPipelineEuroc, VioOnTheExcerptTracksEveryImageAndStaysNearGroundTruth) {
  const std::string path = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(path)) GTEST_SKIP() << "no " << path;
  const Sequence seq = io::readAsl(path);
  VioRunOptions run;
  run.init_from_groundtruth = true;
  const auto out = runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio), run,
                                       VisualFrontendConfig(), nullptr, /*log=*/false);
  EXPECT_EQ(out.lost_images, 0);
  EXPECT_EQ(out.reinitializations, 0);
  const PositionError e = positionError(seq, out.vio.states);
  EXPECT_GT(e.n, 80);
  // The drone hovers (15 cm of path in 4.7 s): the backend sees almost no parallax, triangulates
  // few landmarks and drifts nearly like IMU-only (measured: rms 0.28 m, max 0.65 m). The bound
  // catches a diverging or mis-initialized run, not the accuracy of a moving flight.
  EXPECT_LT(e.rms, 0.4);
  EXPECT_LT(e.max, 0.9);
}

TEST(VisualPipelineEuroc, DefaultStartOnTheHoverFallsBackToStatic) {
  // The excerpt hovers with no parallax and a still IMU (its gyro mean is a 0.08 rad/s bias):
  // the default start is the static one, at the first image after 0.5 s of IMU.
  const std::string path = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(path)) GTEST_SKIP() << "no " << path;
  const Sequence seq = io::readAsl(path);
  // The hover is IMU-dominated (few landmarks triangulate), so one run's error is one draw of
  // a chaotic process: 0.03-0.32 m over image-noise seeds, and a change of round-off anywhere
  // moves it within that range. The bound is on the mean over four seeds; it catches a
  // diverging start, not the accuracy of a moving flight.
  double sum = 0.0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    VioRunOptions run;
    run.image_noise_sigma = 1.0;
    run.seed = seed;
    const auto out = runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio), run,
                                    VisualFrontendConfig(), nullptr, /*log=*/false);
    EXPECT_EQ(out.vio.start, StartKind::kStaticAtRest);
    EXPECT_LT(secondsBetween(seq.images.front().t, out.vio.start_t), 0.6);
    EXPECT_GT(out.vio.states.size(), 80u);
    EXPECT_LE(out.lost_images, 10);
    const double rms = alignedPositionRms(seq, out.vio.states);
    std::printf("seed %u: %.4f m\n", seed, rms);
    sum += rms;
  }
  EXPECT_LT(sum / 4, 0.25);
}

}  // namespace
}  // namespace hdvio
