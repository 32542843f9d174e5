// The README's example program (apps/example/stream_vio_main.cc) prints, image by image, the
// trajectory hdvio_run writes for the same flight with `method: vio` on images and every other
// key at its default; bad input is one error line and exit code 2.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../common/run_command.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

struct Row {
  double t = 0, x = 0, y = 0, z = 0;
};

TEST(StreamExample, PrintsTheTrajectoryOfHdvioRunWithDefaults) {
  const std::string dataset = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(dataset)) GTEST_SKIP() << "no " << dataset;
  const test::CommandOutcome example =
      test::runCommand(std::string(HDVIO_STREAM_EXAMPLE_BINARY) + " " + dataset);
  ASSERT_EQ(example.exit_code, 0) << example.output;
  std::vector<Row> printed;
  std::istringstream lines(example.output);
  for (std::string line, p; std::getline(lines, line);) {
    Row r;
    std::istringstream(line) >> r.t >> p >> r.x >> r.y >> r.z;
    printed.push_back(r);
  }

  const fs::path out = fs::temp_directory_path() / ("hdvio_stream_example_" + std::to_string(getpid()));
  fs::create_directories(out);
  std::ofstream(out / "vio.yaml") << "method: vio\nfrontend: {source: images}\n";
  const test::CommandOutcome run =
      test::runCommand(std::string(HDVIO_RUN_BINARY) + " --config " + (out / "vio.yaml").string() +
                       " --dataset " + dataset + " --evaluate=false --out " + (out / "run").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream traj(out / "run" / "stamped_traj_estimate.txt");
  std::vector<Row> written;
  for (std::string line; std::getline(traj, line);) {
    if (line.empty() || line[0] == '#') continue;
    Row r;
    std::istringstream(line) >> r.t >> r.x >> r.y >> r.z;
    written.push_back(r);
  }
  fs::remove_all(out);
  ASSERT_GT(written.size(), 80u);
  ASSERT_EQ(printed.size(), written.size());
  for (std::size_t k = 0; k < written.size(); ++k) {
    EXPECT_NEAR(printed[k].t, written[k].t, 1e-3) << k;
    EXPECT_NEAR(printed[k].x, written[k].x, 1e-3) << k;
    EXPECT_NEAR(printed[k].y, written[k].y, 1e-3) << k;
    EXPECT_NEAR(printed[k].z, written[k].z, 1e-3) << k;
  }
}

TEST(StreamExample, BadInputIsOneErrorAndExitCodeTwo) {
  const test::CommandOutcome missing =
      test::runCommand(std::string(HDVIO_STREAM_EXAMPLE_BINARY) + " /nonexistent/flight");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_EQ(missing.output.rfind("error: ", 0), 0u) << missing.output;
  EXPECT_EQ(test::runCommand(HDVIO_STREAM_EXAMPLE_BINARY).exit_code, 2);
}

}  // namespace
}  // namespace hdvio
