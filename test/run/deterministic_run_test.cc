// The same command on the same data writes the same files: hdvio_run on camera images in two
// processes, the second beside busy loops on every core (so that thread timing, allocation
// order and any clock-based decision would differ), compared byte for byte. Only the timing
// files are left out: they hold measured times.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "../common/file_text.h"
#include "../common/rendered_flight.h"
#include "../common/run_command.h"
#include "hdvio/core/config.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

using test::readFile;

// Every result file but the measured times, by path relative to dir.
std::vector<fs::path> resultFiles(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (name.rfind("timing", 0) == 0) continue;
    out.push_back(fs::relative(e.path(), dir));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Spins one thread per core until destroyed.
class BusyLoops {
 public:
  BusyLoops() {
    const unsigned n = std::max(2u, std::thread::hardware_concurrency());
    for (unsigned i = 0; i < n; ++i)
      threads_.emplace_back([this] {
        volatile double x = 1.0;
        while (!stop_.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
      });
  }
  ~BusyLoops() {
    stop_ = true;
    for (auto& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

void expectSameFiles(const fs::path& a, const fs::path& b) {
  const std::vector<fs::path> fa = resultFiles(a), fb = resultFiles(b);
  ASSERT_EQ(fa, fb);
  ASSERT_GE(fa.size(), 4u);  // trajectory, velocity, biases, config at least
  for (const fs::path& f : fa) {
    SCOPED_TRACE(f.string());
    EXPECT_TRUE(readFile(a / f) == readFile(b / f)) << (a / f) << " and " << (b / f) << " differ";
  }
}

struct Runs {
  fs::path dir;
  test::CommandOutcome quiet, busy;
};

Runs runTwice(const std::string& config, const std::string& dataset, const std::string& tag) {
  Runs r;
  r.dir = fs::temp_directory_path() / ("hdvio_deterministic_" + tag + "_" + std::to_string(getpid()));
  fs::remove_all(r.dir);
  fs::create_directories(r.dir);
  const std::string base = std::string(HDVIO_RUN_BINARY) + " --config " + config + " --dataset " +
                           dataset + " --evaluate=false --out ";
  r.quiet = test::runCommand(base + (r.dir / "quiet").string());
  {
    BusyLoops busy;
    r.busy = test::runCommand(base + (r.dir / "busy").string());
  }
  return r;
}

TEST(DeterministicRun, EurocExcerptOnImagesIsByteIdenticalUnderLoad) {
  const std::string path = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(path)) GTEST_SKIP() << "no " << path;
  const Runs r = runTwice(std::string(HDVIO_SOURCE_DIR) + "/config/experiments/vio_frontend.yaml",
                          path, "euroc");
  ASSERT_EQ(r.quiet.exit_code, 0) << r.quiet.output;
  ASSERT_EQ(r.busy.exit_code, 0) << r.busy.output;
  expectSameFiles(r.dir / "quiet", r.dir / "busy");
  fs::remove_all(r.dir);
}

// A moving start: the KLT tracker and the visual-inertial initialization run on the images
// before the frontend and the smoother take over.
TEST(DeterministicRun, RenderedFlightWithVisualInertialStartIsByteIdenticalUnderLoad) {
  const fs::path dir = fs::temp_directory_path() / ("hdvio_deterministic_flight_" + std::to_string(getpid()));
  const fs::path seq = test::writeRenderedFlight("config/sim/ci_images_moving.yaml", dir);
  // The experiment of the image pipeline tests: 320x240 needs a finer detector grid.
  const fs::path config = dir / "vio_images.yaml";
  std::ofstream(config) << "method: vio\n"
                           "run: {init_from_groundtruth: false}\n"
                           "frontend: {source: images, backend_pose_prior: true, backend_feedback: true,\n"
                           "           detector: {cell_size: 16}}\n";
  const Runs r = runTwice(config.string(), seq.string(), "sim");
  ASSERT_EQ(r.quiet.exit_code, 0) << r.quiet.output;
  ASSERT_EQ(r.busy.exit_code, 0) << r.busy.output;
  ASSERT_NE(r.quiet.output.find("visual-inertial"), std::string::npos) << r.quiet.output;
  expectSameFiles(r.dir / "quiet", r.dir / "busy");
  fs::remove_all(r.dir);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hdvio
