// hdvio_train_displacement with validation flights (data.validation, the IMO release's way of
// choosing its epoch on `val`): trains on all of data.train, validates on the listed flights,
// refuses to mix them with the other hold-out schemes, and measures throughput without --out.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "../common/run_command.h"
#include "hdvio/core/config.h"
#include "hdvio/io/asl.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {

namespace fs = std::filesystem;

class TrainDisplacementApp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hdvio_train_displacement_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    auto config = sim::loadSimConfig(
        ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_tiny.yaml"));
    const auto result = sim::Simulator(config).simulate();
    io::writeAsl(result.sequence, (dir_ / "train").string());
    io::writeAsl(result.sequence, (dir_ / "val").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static std::string writeConfig(const std::string& name, const std::string& data) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << "data:\n" << data
                     << "model: {inputs: thrust_gyro, window: 50, sample_rate_hz: 100, kernel_size: 2,\n"
                        "        widths: [8, 8], dilations: [1, 2]}\n"
                        "training: {stride_samples: 10, batch_size: 16, max_epochs: 1, patience: 5,\n"
                        "           threads: 1, seed: 7}\n";
    return p.string();
  }
  static test::CommandOutcome train(const std::string& config, const std::string& out) {
    return test::runCommand(std::string(HDVIO_TRAIN_DISPLACEMENT_BINARY) + " --config " + config +
                            " --data_root " + dir_.string() + " --out " + (dir_ / out).string() + " 2>&1");
  }
  static fs::path dir_;
};
fs::path TrainDisplacementApp::dir_;

TEST_F(TrainDisplacementApp, ValidationFlightsChooseTheEpoch) {
  const auto o = train(writeConfig("val.yaml", "  train: [train]\n  validation: [val]\n"), "val.tcn");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("val: validation, "), std::string::npos) << o.output;
  // All of train trains (no interleaved blocks held out): 301 samples, a window every 10 from the 50th.
  EXPECT_NE(o.output.find("training windows 26,"), std::string::npos) << o.output;
  EXPECT_TRUE(fs::exists(dir_ / "val.tcn"));
}

TEST_F(TrainDisplacementApp, ValidationFlightsExcludeFolds) {
  const auto o = train(writeConfig("mixed.yaml", "  train: [train]\n  validation: [val]\n"
                                                 "  cross_validation_folds: 3\n"),
                       "mixed.tcn");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_NE(o.output.find("mixed.yaml: data.validation excludes --fold, --epochs and data.cross_validation_folds"),
            std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "mixed.tcn"));
}

// Measuring the training throughput writes no network, so it needs no --out; a training does.
TEST_F(TrainDisplacementApp, ThroughputNeedsNoOutputFile) {
  const std::string config = writeConfig("bench.yaml", "  train: [train]\n  validation: [val]\n");
  const auto o = test::runCommand(std::string(HDVIO_TRAIN_DISPLACEMENT_BINARY) + " --config " + config +
                                  " --data_root " + dir_.string() + " --benchmark_batches 2 2>&1");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("windows per CPU second"), std::string::npos) << o.output;
  const auto no_out = test::runCommand(std::string(HDVIO_TRAIN_DISPLACEMENT_BINARY) + " --config " + config +
                                       " --data_root " + dir_.string() + " 2>&1");
  EXPECT_EQ(no_out.exit_code, 2) << no_out.output;
  EXPECT_NE(no_out.output.find("--out is required"), std::string::npos) << no_out.output;
}

}  // namespace
}  // namespace hdvio
