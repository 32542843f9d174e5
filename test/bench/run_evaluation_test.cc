// hdvio_run's own evaluation (apps/run/src/run_evaluation.cc): numbers from the sequence's
// ground truth, and never an exception or a failure for a run whose results are complete.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "hdvio/run/run_evaluation.h"

namespace hdvio::run {
namespace {

RunEvaluationOptions noPlots() {
  RunEvaluationOptions o;
  o.plots = false;
  return o;
}
namespace fs = std::filesystem;

// A 2 s flight along x at 1 m/s with a slow yaw, ground truth at 100 Hz.
Sequence straightFlight() {
  Sequence seq;
  seq.name = "straight";
  seq.source = "memory";
  for (int i = 0; i <= 200; ++i) {
    GroundTruthState s;
    s.t = i * 10'000'000LL;
    s.T_WB.p = Vec3(0.01 * i, 0.0, 1.0);
    s.T_WB.q = Quat(Eigen::AngleAxisd(0.002 * i, Vec3::UnitZ()));
    s.v_W = Vec3(1.0, 0.0, 0.0);
    s.has_velocity = true;
    seq.groundtruth.push_back(s);
  }
  return seq;
}

class RunEvaluation : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hdvio_run_evaluation_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "result");
    std::ofstream(dir_ / "result" / "config.yaml") << "method: vio\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Every 5th ground-truth pose up to pose `last`, shifted by `offset` in x and `dt_s` in time.
  void writeEstimate(const Sequence& seq, double offset, double dt_s, std::size_t last = 1u << 30) {
    std::ofstream f(dir_ / "result" / "stamped_traj_estimate.txt");
    f << "# timestamp[s] tx ty tz qx qy qz qw\n";
    char line[256];
    for (std::size_t i = 0; i < seq.groundtruth.size() && i <= last; i += 5) {
      const auto& s = seq.groundtruth[i];
      std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n",
                    toSeconds(s.t) + dt_s, s.T_WB.p.x() + offset, s.T_WB.p.y(), s.T_WB.p.z(),
                    s.T_WB.q.x(), s.T_WB.q.y(), s.T_WB.q.z(), s.T_WB.q.w());
      f << line;
    }
  }
  fs::path dir_;
};

TEST_F(RunEvaluation, ExactEstimateHasZeroErrorAndIsWritten) {
  const Sequence seq = straightFlight();
  writeEstimate(seq, 0.0, 0.0);
  // Not an ASL folder: the ground truth comes from the sequence itself.
  ASSERT_TRUE(evaluateRun(seq, (dir_ / "no_such_dataset").string(), (dir_ / "result").string(), noPlots()));
  const fs::path json = dir_ / "result" / "evaluation" / "metrics.json";
  ASSERT_TRUE(fs::exists(json));
  std::ifstream in(json);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"name\": \"vio\""), std::string::npos) << text;
  const std::size_t at = text.find("\"rmse\": ", text.find("ate_translation_m"));
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(std::strtod(text.c_str() + at + 8, nullptr), 1e-6);
  EXPECT_NE(text.find("\"matched\": 41"), std::string::npos) << text;
}

TEST_F(RunEvaluation, ShiftedEstimateGivesItsShiftWithoutAlignment) {
  const Sequence seq = straightFlight();
  writeEstimate(seq, 0.3, 0.0);
  RunEvaluationOptions options;
  options.plots = false;
  options.alignment = eval::AlignmentType::kNone;
  ASSERT_TRUE(evaluateRun(seq, "", (dir_ / "result").string(), options));
  std::ifstream in(dir_ / "result" / "evaluation" / "metrics.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("\"rmse\": ", text.find("ate_translation_m"));
  EXPECT_NEAR(std::strtod(text.c_str() + at + 8, nullptr), 0.3, 1e-6);
}

// A run on the first 0.5 s of the 2 s flight (run.duration_s): the rpg sub-trajectory lengths
// are 10 %, ..., 50 % of the 0.5 m it covered, not of the flight's 2 m (which no pair spans).
TEST_F(RunEvaluation, RunOnPartOfAFlightGetsLengthsOfThatPart) {
  const Sequence seq = straightFlight();
  writeEstimate(seq, 0.0, 0.0, 50);
  const auto firstDistance = [this] {
    std::ifstream in(dir_ / "result" / "evaluation" / "metrics.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find("\"distance_m\": ");
    return at == std::string::npos ? -1.0 : std::strtod(text.c_str() + at + 14, nullptr);
  };
  ASSERT_TRUE(evaluateRun(seq, "", (dir_ / "result").string(), noPlots()));
  EXPECT_NEAR(firstDistance(), 0.2, 1e-9);  // the whole flight's
  RunEvaluationOptions options;
  options.plots = false;
  options.ground_truth_span = {seq.groundtruth.front().t, seq.groundtruth[50].t};
  ASSERT_TRUE(evaluateRun(seq, "", (dir_ / "result").string(), options));
  EXPECT_NEAR(firstDistance(), 0.05, 1e-9);
}

TEST_F(RunEvaluation, ProblemsAreReportedNotThrown) {
  Sequence no_gt = straightFlight();
  writeEstimate(no_gt, 0.0, 0.0);
  no_gt.groundtruth.clear();
  EXPECT_FALSE(evaluateRun(no_gt, "", (dir_ / "result").string(), noPlots()));
  EXPECT_FALSE(fs::exists(dir_ / "result" / "evaluation"));
  // Stamps 100 s off: nothing associates, an InputError inside; false, no metrics.json.
  const Sequence seq = straightFlight();
  writeEstimate(seq, 0.0, 100.0);
  EXPECT_FALSE(evaluateRun(seq, "", (dir_ / "result").string(), noPlots()));
  EXPECT_FALSE(fs::exists(dir_ / "result" / "evaluation" / "metrics.json"));
}

}  // namespace
}  // namespace hdvio::run
