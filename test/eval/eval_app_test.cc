// hdvio_eval end to end: exit codes and one-line errors for bad input, evo's numbers through the
// tool, and a Blackbird flight against a perturbed copy (yaw offset + random-walk drift).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hdvio/eval/alignment.h"
#include "hdvio/eval/association.h"
#include "hdvio/eval/pose_errors.h"
#include "hdvio/eval/report.h"
#include "hdvio/eval/statistics.h"
#include "hdvio/eval/trajectory_io.h"

namespace hdvio::eval {
namespace {
namespace fs = std::filesystem;

const std::string kData = HDVIO_DATA_DIR;
const std::string kBlackbird =
    kData + "/blackbird/clover_yawForward_maxSpeed5p0/val/stamped_groundtruth_imu.txt";

struct RunResult {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class EvalApp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hdvio_eval_app_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  RunResult run(const std::string& args) {
    const std::string cmd = std::string(HDVIO_EVAL_BINARY) + " " + args + " > " + (dir_ / "stdout").string() +
                            " 2> " + (dir_ / "stderr").string();
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir_ / "stdout");
    r.err = slurp(dir_ / "stderr");
    return r;
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

// First "rmse" after `key` in metrics.json.
double jsonRmse(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\"");
  if (at == std::string::npos) return NAN;
  std::smatch m;
  const std::string rest = json.substr(at);
  if (!std::regex_search(rest, m, std::regex("\"rmse\": ([-0-9.eE+]+)"))) return NAN;
  return std::stod(m[1]);
}

// metrics.json parses as JSON: a statistic without samples (NaN) is null, a metric that was
// not computed is null, names and notes round-trip through the escaping.
TEST(EvalReportJson, MissingValuesAreNullAndTextRoundTrips) {
  EvaluationReport report;
  report.ground_truth_source = "gt \"dir\"\\x";
  EstimateResult r;
  r.name = "a\nb";
  r.num_poses = 5;
  r.ate_translation = computeStatistics({1.0, 2.0});
  r.ate_rotation_deg = computeStatistics({});  // count 0, NaN fields
  r.notes = {"tab\there", "\x01"};
  report.results.push_back(r);
  const nlohmann::json j = nlohmann::json::parse(formatJson(report));
  EXPECT_EQ(j["ground_truth"], report.ground_truth_source);
  EXPECT_EQ(j["options"]["alignment"], "posyaw");
  EXPECT_EQ(j["options"]["evo_rpe_delta"].get<double>(), 10.0);
  ASSERT_EQ(j["estimates"].size(), 1u);
  const nlohmann::json& e = j["estimates"][0];
  EXPECT_EQ(e["name"], "a\nb");
  EXPECT_EQ(e["index"], 0);
  EXPECT_EQ(e["poses"], 5);
  EXPECT_EQ(e["alignment"]["rotation"].size(), 9u);
  EXPECT_EQ(e["ate_translation_m"]["count"], 2);
  EXPECT_EQ(e["ate_translation_m"]["rmse"].get<double>(), r.ate_translation.rmse);  // exact
  EXPECT_EQ(e["ate_rotation_deg"]["count"], 0);
  EXPECT_TRUE(e["ate_rotation_deg"]["rmse"].is_null());
  EXPECT_TRUE(e["evo_rpe_translation_m"].is_null());
  EXPECT_TRUE(e["velocity_m_s"].is_null());
  EXPECT_TRUE(e["relative_errors"].is_array());
  EXPECT_EQ(e["notes"], nlohmann::json({"tab\there", "\x01"}));
}

TEST_F(EvalApp, MissingFlagsPrintUsageAndExit2) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("--gt x.txt").code, 2);
}

TEST_F(EvalApp, MalformedEstimateGivesOneLineErrorAndNoResult) {
  const std::string gt = write("gt.txt", "1.0 0 0 0 0 0 0 1\n1.1 1 0 0 0 0 0 1\n1.2 2 0 0 0 0 0 1\n");
  const std::string bad = write("bad.txt", "1.0 0 0 0 0 0 0 1\n1.1 0 0 nan 0 0 0 1\n");
  const RunResult r = run("--gt " + gt + " --est bad=" + bad + " --out " + (dir_ / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: " + bad + ":2: non-finite value: 'nan'\n");
  EXPECT_FALSE(fs::exists(dir_ / "out" / "metrics.json"));

  const std::string unordered = write("unordered.txt", "1.1 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  const RunResult r2 = run("--gt " + gt + " --est " + unordered);
  EXPECT_EQ(r2.code, 2);
  EXPECT_NE(r2.err.find(unordered + ":2: timestamps are not increasing"), std::string::npos) << r2.err;

  EXPECT_EQ(run("--gt " + gt + " --est a=" + gt + " --align banana").code, 2);
  EXPECT_EQ(run("--gt " + gt + " --est a=" + (dir_ / "nope.txt").string()).code, 2);
}

TEST_F(EvalApp, ReproducesEvoReferenceThroughTheTool) {
  const std::string dir = kData + "/reference_metrics";
  if (!fs::exists(dir + "/KITTI_00_gt.txt")) GTEST_SKIP() << "missing " << dir;
  const RunResult r = run("--gt " + dir + "/KITTI_00_gt.txt --est orb=" + dir +
                          "/KITTI_00_ORB.txt --align se3 --rpe_fractions= --out " + (dir_ / "kitti").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir_ / "kitti" / "metrics.json");
  EXPECT_NEAR(jsonRmse(json, "ate_translation_m"), 1.3034497145650266, 1.3e-6);
  EXPECT_NEAR(jsonRmse(json, "evo_rpe_translation_m"), 0.22626134329310163, 2.3e-7);
  EXPECT_NE(r.out.find("| orb | 4541/4541 | 1.3034 |"), std::string::npos) << r.out;
}

// evo's V1_02 ORB-SLAM estimate repeats 4 stamps: a warning with the count, evo's ATE.
TEST_F(EvalApp, RepeatedStampsWarnAndMatchEvo) {
  const std::string dir = std::string(HDVIO_SOURCE_DIR) + "/test/eval/data";
  const std::string est = dir + "/evo_V102_ORB.txt";
  const RunResult r = run("--gt " + dir + "/evo_V102_groundtruth_excerpt.csv --est orb=" + est +
                          " --align se3 --rpe_fractions= --out " + (dir_ / "v102").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + est + ": 4 poses repeat the previous timestamp"), std::string::npos)
      << r.err;
  EXPECT_NEAR(jsonRmse(slurp(dir_ / "v102" / "metrics.json"), "ate_translation_m"), 0.09172711520685754, 1e-5);
}

// Writes gt transformed by a yaw offset + translation, plus a seeded random-walk drift.
std::string writePerturbed(const Trajectory& gt, const fs::path& path, double yaw, double drift_sigma) {
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss(0.0, drift_sigma);
  const Mat3 Rz = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  Vec3 drift = Vec3::Zero();
  std::ofstream out(path);
  out << "# timestamp[s] tx ty tz qx qy qz qw\n";
  char line[256];
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (drift_sigma > 0) drift += Vec3(gauss(rng), gauss(rng), gauss(rng));
    const Vec3 p = Rz * gt.p[i] + Vec3(1.0, -2.0, 0.5) + drift;
    const Quat q(Rz * gt.R[i]);
    std::snprintf(line, sizeof(line), "%lld.%09lld %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                  static_cast<long long>(gt.t[i] / kNanosPerSecond),
                  static_cast<long long>(gt.t[i] % kNanosPerSecond), p.x(), p.y(), p.z(), q.x(), q.y(),
                  q.z(), q.w());
    out << line;
  }
  return path.string();
}

TEST_F(EvalApp, BlackbirdPerturbedCopy) {
  if (!fs::exists(kBlackbird)) GTEST_SKIP() << "missing " << kBlackbird;
  const Trajectory gt = readTrajectory(kBlackbird);
  const std::string rigid = writePerturbed(gt, dir_ / "rigid.txt", 0.6, 0.0);
  const std::string drifting = writePerturbed(gt, dir_ / "drift.txt", 0.6, 0.003);

  // A pure yaw + translation offset is removed exactly by posyaw, not by "none".
  RunResult r = run("--gt " + kBlackbird + " --est rigid=" + rigid + " --out " + (dir_ / "a").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::string json = slurp(dir_ / "a" / "metrics.json");
  EXPECT_LT(jsonRmse(json, "ate_translation_m"), 1e-6);
  EXPECT_LT(jsonRmse(json, "ate_rotation_deg"), 1e-4);
  r = run("--gt " + kBlackbird + " --est rigid=" + rigid + " --align none --out " + (dir_ / "b").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(jsonRmse(slurp(dir_ / "b" / "metrics.json"), "ate_translation_m"), 1.0);

  // With drift the tool agrees with the library, and the recovered yaw is near the offset.
  r = run("--gt " + kBlackbird + " --est drift=" + drifting + " --out " + (dir_ / "c").string());
  ASSERT_EQ(r.code, 0) << r.err;
  json = slurp(dir_ / "c" / "metrics.json");
  const Trajectory est = readTrajectory(drifting);
  const AssociatedPair pair = associate(gt, est, AssociationOptions{});
  ASSERT_EQ(pair.est.size(), gt.size());
  const SimilarityTransform T = computeAlignment(AlignmentType::kPosYaw, pair.ref, pair.est, -1);
  EXPECT_NEAR(std::atan2(T.R(0, 1), T.R(0, 0)), 0.6, 0.02);  // R^-1 undoes the +0.6 rad yaw
  const double ate = computeStatistics(absoluteErrors(pair.ref, applyAlignment(T, pair.est)).translation).rmse;
  EXPECT_NEAR(jsonRmse(json, "ate_translation_m"), ate, 1e-9 * ate);
  EXPECT_GT(ate, 0.02);
  EXPECT_LT(ate, 1.0);
}

TEST_F(EvalApp, PlotsProduceAllFigures) {
  if (!fs::exists(kBlackbird)) GTEST_SKIP() << "missing " << kBlackbird;
  if (std::system("/usr/bin/python3 -c 'import matplotlib, numpy' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-matplotlib not installed";
  const Trajectory gt = readTrajectory(kBlackbird);
  const std::string drifting = writePerturbed(gt, dir_ / "drift.txt", -0.3, 0.003);
  const RunResult r = run("--gt " + kBlackbird + " --est drift=" + drifting + " --plots --out " +
                          (dir_ / "p").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* png : {"trajectory_top.png", "trajectory_side.png", "translation_error.png",
                          "relative_error_boxplot.png"}) {
    EXPECT_TRUE(fs::exists(dir_ / "p" / png)) << png;
    if (fs::exists(dir_ / "p" / png)) {
      EXPECT_GT(fs::file_size(dir_ / "p" / png), 10000u) << png;
    }
  }
}

}  // namespace
}  // namespace hdvio::eval
