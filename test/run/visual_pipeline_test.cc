// The image pipeline of the visual methods: the semi-direct frontend feeding the sliding-window
// backend on a small rendered flight and on the EuRoC excerpt, estimates checked against
// ground truth; missing images are a clear error.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "../common/run_command.h"
#include "hdvio/backend/vio_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/io/asl.h"
#include "hdvio/run/visual_image_runner.h"
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

run::VisualFrontendConfig smallImageFrontend() {
  run::VisualFrontendConfig c;
  c.options.detector.cell_size = 16;  // 320x240: the default 32 px grid leaves too few corners
  return c;
}

class VisualPipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hdvio_visual_pipeline_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const auto config = sim::loadSimConfig(
        ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_images.yaml"));
    const sim::Simulator simulator(config);
    sim::SimulationResult result = simulator.simulate();
    simulator.renderImages(&result, (dir_ / "rendered").string());
    result.sequence.landmark_observations.clear();  // images only
    io::writeAsl(result.sequence, (dir_ / "seq").string());
    fs::remove_all(dir_ / "rendered");
    sequence_ = new Sequence();
    *sequence_ = io::readAsl((dir_ / "seq").string());
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
  const auto out = run::runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVio), run,
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
  const auto out = run::runVioOnImages(*sequence_, defaultVioBackendOptions(VioMethod::kVimo),
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
  const auto out = run::runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio), run,
                                       smallImageFrontend(), nullptr, /*log=*/false);
  EXPECT_GE(out.lost_images, covered);
  EXPECT_LE(out.lost_images, covered + 4);
  EXPECT_GE(out.reinitializations, 1);
  EXPECT_FALSE(out.images.back().stage == frontend::TrackingStage::kRelocalizing);
  EXPECT_TRUE(out.images.back().used_by_backend);
  const PositionError e = positionError(seq, out.vio.states);
  EXPECT_LT(e.max, 0.3);
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

TEST(VisualPipelineEuroc, VioOnTheExcerptTracksEveryImageAndStaysNearGroundTruth) {
  const std::string path = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(path)) GTEST_SKIP() << "no " << path;
  const Sequence seq = io::readAsl(path);
  VioRunOptions run;
  run.init_from_groundtruth = true;
  const auto out = run::runVioOnImages(seq, defaultVioBackendOptions(VioMethod::kVio), run,
                                       run::VisualFrontendConfig(), nullptr, /*log=*/false);
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

}  // namespace
}  // namespace hdvio
