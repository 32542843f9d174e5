// Readers: the real formats load, malformed files fail with an InputError naming file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "hdvio/core/error.h"
#include "hdvio/eval/estimate_inputs.h"
#include "hdvio/eval/trajectory_io.h"

namespace hdvio::eval {
namespace {
namespace fs = std::filesystem;

const std::string kData = HDVIO_DATA_DIR;

class EvalTempFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hdvio_eval_io_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // The error must name the file and the line.
  void expectError(const std::string& path, long line, const std::string& fragment,
                   TrajectoryFormat format = TrajectoryFormat::kAuto) {
    try {
      readTrajectory(path, format);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

const char* kGoodTum =
    "# timestamp[s] tx ty tz qx qy qz qw\n"
    "1.0 0 0 0 0 0 0 1\n"
    "1.1 1 0 0 0 0 0 1\n";

TEST_F(EvalTempFiles, TumReadsExactNanoseconds) {
  const Trajectory t = readTrajectory(write("a.txt", "1525745895.001626729965 0 0 0 0 0 0 1\n"));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t.t[0], 1525745895001626730LL);
  const Trajectory good = readTrajectory(write("b.txt", kGoodTum));
  EXPECT_EQ(good.size(), 2u);
  EXPECT_EQ(good.t[1], 1'100'000'000LL);
}

TEST_F(EvalTempFiles, MalformedTumFilesNameTheLine) {
  expectError(write("nan.txt", "# h\n1.0 0 0 0 0 0 0 1\n1.1 nan 0 0 0 0 0 1\n"), 3, "non-finite");
  expectError(write("cols.txt", "1.0 0 0 0 0 0 0 1\n1.1 0 0 0 0 0 1\n"), 2, "expected 8 columns");
  expectError(write("order.txt", "1.0 0 0 0 0 0 0 1\n0.9 0 0 0 0 0 0 1\n"), 2, "not increasing");
  expectError(write("back.txt", "1.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n0.9 0 0 0 0 0 0 1\n"), 3,
              "not increasing");
  expectError(write("quat.txt", "1.0 0 0 0 0 0 0 2\n"), 1, "unit length");
  expectError(write("word.txt", "1.0 0 0 0 0 0 0 1\n1.1 0 x 0 0 0 0 1\n"), 2, "not a number");
  expectError(write("empty.txt", "# only a header\n"), 0, "no data lines");
  expectError(write("seven.txt", "1 2 3 4 5 6 7\n"), 1, "cannot tell the trajectory format");
  expectError((dir_ / "missing.txt").string(), 0, "no such file");
}

// evo keeps every pose of a repeated stamp (its readers do not check order); so do we, counted.
TEST_F(EvalTempFiles, RepeatedStampsAreKeptAndCounted) {
  const Trajectory tum = readTrajectory(
      write("dup.txt", "1.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n1.1 2 0 0 0 0 0 1\n1.1 3 0 0 0 0 0 1\n"));
  ASSERT_EQ(tum.size(), 4u);
  EXPECT_EQ(tum.repeated_stamps, 2u);
  EXPECT_EQ(tum.p[1].x(), 1.0);
  EXPECT_NE(repeatedStampsWarning(tum).find(": 2 poses repeat the previous timestamp"), std::string::npos);
  const Trajectory euroc = readTrajectory(write(
      "dup.csv", "#timestamp [ns],x,y,z,qw,qx,qy,qz\n1000000000000,0,0,0,1,0,0,0\n1000000000000,1,0,0,1,0,0,0\n"));
  EXPECT_EQ(euroc.repeated_stamps, 1u);
  EXPECT_EQ(readTrajectory(write("ok.txt", kGoodTum)).repeated_stamps, 0u);
  EXPECT_EQ(repeatedStampsWarning(readTrajectory(write("ok2.txt", kGoodTum))), "");
}

TEST_F(EvalTempFiles, MalformedKittiAndEurocFiles) {
  expectError(write("k.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n"), 2, "expected 12 columns",
              TrajectoryFormat::kKitti);
  expectError(write("k2.txt", "2 0 0 0 0 1 0 0 0 0 1 0\n"), 1, "not a rotation");
  expectError(write("e.csv", "#timestamp [ns],x,y,z,qw,qx,qy,qz\n1000000000000,0,0,0,1,0,0,0\n"
                             "1000000000001,0,,0,1,0,0,0\n"), 3, "empty field");
}

TEST_F(EvalTempFiles, EstimateListParsing) {
  const auto specs = parseEstimateList("a=x.txt,b=dir:velocity=v.csv:force=f.csv");
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[1].name, "b");
  EXPECT_EQ(*specs[1].velocity_path, "v.csv");
  EXPECT_EQ(*specs[1].force_path, "f.csv");
  EXPECT_THROW(parseEstimateList("a=x,a=y"), InputError);
  EXPECT_THROW(parseEstimateList("a b=x"), InputError);
  EXPECT_THROW(parseEstimateList("a=x:speed=v.csv"), InputError);
}

TEST(EvalRealFiles, BlackbirdGroundTruthIsTumWithVelocity) {
  const std::string path = kData + "/blackbird/clover_yawForward_maxSpeed5p0/val/stamped_groundtruth_imu.txt";
  if (!fs::exists(path)) GTEST_SKIP() << "missing " << path;
  EXPECT_EQ(detectTrajectoryFormat(path), TrajectoryFormat::kTum);
  const Trajectory t = readTrajectory(path);
  EXPECT_EQ(t.size(), 3000u);
  EXPECT_TRUE(t.hasVelocity());
  EXPECT_NEAR(secondsBetween(t.t.front(), t.t.back()), 29.99, 0.02);
}

TEST(EvalRealFiles, EurocAslFolderAndCsv) {
  const std::string folder = kData + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(folder)) GTEST_SKIP() << "missing " << folder;
  const Trajectory t = readTrajectory(folder);
  EXPECT_EQ(t.size(), 115u);  // 116 lines minus the header
  EXPECT_TRUE(t.hasVelocity());
  EXPECT_EQ(t.t[0], 1403715273262142976LL);
  // q_RS (w, x, y, z) = (0.069433, -0.824237, -0.106942, -0.551702) on the first line.
  const Quat q(t.R[0]);
  EXPECT_NEAR(std::abs(q.w()), 0.069433, 1e-5);
  const Trajectory csv = readTrajectory(folder + "/mav0/state_groundtruth_estimate0/data.csv");
  EXPECT_EQ(csv.size(), t.size());
}

}  // namespace
}  // namespace hdvio::eval
