// HDVIO without motion capture, end to end on a short rendered flight: vio on the images
// (hdvio_run, its own start) -> hdvio_train supervised by that estimate (data.train_estimates)
// -> hdvio on the same images with the model. And the folder mistakes a user makes: one error
// naming the file, exit 2, no weight file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../common/rendered_flight.h"
#include "../common/run_command.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

std::string text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string trainConfig(const fs::path& dir, const std::string& flight, const std::string& estimate) {
  const fs::path p = dir / "train.yaml";
  std::ofstream(p) << "data:\n  train: [" << flight << "]\n  train_estimates: [" << estimate
                   << "]\n  validation_block_seconds: 0.5\n  validation_every: 3\n"
                      "model: {window: 10, sample_rate_hz: 100, kernel_size: 2, widths: [8, 8],\n"
                      "        dilations: [1, 2], drag_law: fit}\n"
                      "training: {segment_seconds: 0.25, stride_samples: 4, batch_size: 32,\n"
                      "           learning_rate: 1.0e-3, max_epochs: 3, patience: 3, seed: 7, threads: 1}\n";
  return p.string();
}

TEST(TrainFromEstimate, VioEstimateTrainsAModelHdvioRunsWith) {
  const fs::path dir = fs::temp_directory_path() / ("hdvio_train_from_estimate_" + std::to_string(getpid()));
  const fs::path seq = test::writeRenderedFlight("config/sim/ci_images_moving.yaml", dir);
  std::ofstream(dir / "vio.yaml") << "method: vio\nfrontend: {source: images, detector: {cell_size: 16}}\n";
  const test::CommandOutcome vio = test::runCommand(
      std::string(HDVIO_RUN_BINARY) + " --config " + (dir / "vio.yaml").string() + " --dataset " +
      seq.string() + " --evaluate=false --out " + (dir / "vio").string());
  ASSERT_EQ(vio.exit_code, 0) << vio.output;

  const test::CommandOutcome train = test::runCommand(
      std::string(HDVIO_TRAIN_BINARY) + " --config " + trainConfig(dir, seq.string(), (dir / "vio").string()) +
      " --out " + (dir / "model.tcn").string());
  ASSERT_EQ(train.exit_code, 0) << train.output;
  const std::string model = text(dir / "model.tcn");
  EXPECT_EQ(model.rfind("hdvio_tcn 7\n", 0), 0u) << model.substr(0, 200);
  EXPECT_NE(model.find("\nsupervision estimate\nenvelope "), std::string::npos);
  EXPECT_NE(model.find("# supervision of " + seq.string() + ": the estimate in " + (dir / "vio").string()),
            std::string::npos);

  std::ofstream(dir / "hdvio.yaml") << "method: hdvio\nfrontend: {source: images, detector: {cell_size: 16}}\n"
                                       "residual_force: {type: tcn, weights: "
                                    << (dir / "model.tcn").string() << "}\n";
  const test::CommandOutcome hdvio = test::runCommand(
      std::string(HDVIO_RUN_BINARY) + " --config " + (dir / "hdvio.yaml").string() + " --dataset " +
      seq.string() + " --evaluate=false --out " + (dir / "hdvio").string());
  ASSERT_EQ(hdvio.exit_code, 0) << hdvio.output;
  EXPECT_TRUE(fs::exists(dir / "hdvio" / "stamped_traj_estimate.txt"));
  // The model's training envelope reached the run.
  EXPECT_NE(text(dir / "hdvio" / "config.yaml").find("model_speed_max: "), std::string::npos);

  // A result folder without velocities: one error naming the file, no weight file.
  fs::remove(dir / "vio" / "stamped_velocity_estimate.csv");
  const test::CommandOutcome bad = test::runCommand(
      std::string(HDVIO_TRAIN_BINARY) + " --config " + trainConfig(dir, seq.string(), (dir / "vio").string()) +
      " --out " + (dir / "bad.tcn").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("error: " + (dir / "vio" / "stamped_velocity_estimate.csv").string() + ": missing"),
            std::string::npos)
      << bad.output;
  EXPECT_FALSE(fs::exists(dir / "bad.tcn"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hdvio
