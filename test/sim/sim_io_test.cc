// The simulator's output reads back through the ASL reader; hdvio_sim rejects bad input with
// one clear error line and exit code 2, writing nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/sim/simulator.h"
#include "sim_test_util.h"

namespace hdvio::sim {
namespace {
namespace fs = std::filesystem;

struct ToolRun {
  int code;
  std::string err, out;
};

ToolRun runSim(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt", out = dir / "stdout.txt";
  const std::string cmd = std::string(HDVIO_SIM_BIN) + " " + args + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err), slurp(out)};
}

TEST(SimIo, WrittenSequenceReadsBackThroughTheAslReader) {
  const fs::path dir = testing::freshTempDir("io");
  SimConfig c = testing::smallVisualConfig();
  c.imu.noise = true;
  c.vehicle.thrust_noise = 0.05;
  const Simulator sim(c);
  SimulationResult r = sim.simulate();
  sim.renderImages(&r, (dir / "seq" / "mav0" / "cam0" / "data").string());
  io::writeAsl(r.sequence, (dir / "seq").string());
  const Sequence back = io::readAsl((dir / "seq").string());
  const Sequence& seq = r.sequence;
  ASSERT_EQ(back.imu.size(), seq.imu.size());
  ASSERT_EQ(back.groundtruth.size(), seq.groundtruth.size());
  ASSERT_EQ(back.thrust.size(), seq.thrust.size());
  ASSERT_EQ(back.rotor.size(), seq.rotor.size());
  ASSERT_EQ(back.forces.size(), seq.forces.size());
  ASSERT_EQ(back.images.size(), seq.images.size());
  ASSERT_EQ(back.landmarks.size(), seq.landmarks.size());
  ASSERT_EQ(back.landmark_observations.size(), seq.landmark_observations.size());
  for (size_t k = 0; k < seq.imu.size(); ++k) {
    ASSERT_EQ(back.imu[k].t, seq.imu[k].t);
    ASSERT_LT((back.imu[k].accel - seq.imu[k].accel).norm(), 1e-12);
    ASSERT_LT((back.groundtruth[k].T_WB.p - seq.groundtruth[k].T_WB.p).norm(), 1e-12);
    ASSERT_LT((back.forces[k].drag - seq.forces[k].drag).norm(), 1e-12);
  }
  ASSERT_TRUE(back.camera.has_value());
  EXPECT_EQ(back.camera->width, 160);
  EXPECT_NEAR(back.camera->fu, c.camera.fu, 1e-12);
  EXPECT_LT((back.camera->T_BS.p - c.camera.T_BS.p).norm(), 1e-12);
  ASSERT_TRUE(back.rotor_calibration.has_value());
  EXPECT_NEAR(back.rotor_calibration->thrust_coefficient, c.vehicle.thrust_coefficient, 1e-18);
  const cv::Mat img = cv::imread(back.images[3].path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.type(), CV_8UC1);
  EXPECT_EQ(img.cols, 160);
  EXPECT_EQ(cv::norm(img, sim.renderFrame(secondsBetween(c.start_time_ns, back.images[3].t), 3), cv::NORM_INF), 0.0);
  fs::remove_all(dir);
}

TEST(SimIo, ToolWritesTheCiScenarioAndRefusesToOverwrite) {
  const fs::path dir = testing::freshTempDir("tool");
  const std::string cfg = std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_tiny.yaml";
  const ToolRun ok = runSim("--config " + cfg + " --out " + (dir / "out").string(), dir);
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "sim_config.yaml"));
  const Sequence seq = io::readAsl((dir / "out").string());
  EXPECT_EQ(seq.imu.size(), 601u);
  EXPECT_EQ(seq.images.size(), 31u);
  EXPECT_FALSE(seq.landmark_observations.empty());
  // The effective config regenerates the same flight.
  const ToolRun again = runSim("--config " + (dir / "out" / "sim_config.yaml").string() + " --out " +
                               (dir / "out2").string(), dir);
  ASSERT_EQ(again.code, 0) << again.err;
  const Sequence seq2 = io::readAsl((dir / "out2").string());
  ASSERT_EQ(seq2.imu.size(), seq.imu.size());
  EXPECT_EQ(seq2.imu.back().accel, seq.imu.back().accel);
  const ToolRun refused = runSim("--config " + cfg + " --out " + (dir / "out").string(), dir);
  EXPECT_EQ(refused.code, kExitBadInput);
  EXPECT_NE(refused.err.find("--overwrite"), std::string::npos) << refused.err;
  fs::remove_all(dir);
}

TEST(SimIo, BadConfigsGiveOneClearErrorAndNoOutput) {
  const fs::path dir = testing::freshTempDir("bad");
  const std::string base =
      "duration: 2.0\ntrajectory:\n  type: circle\n  radius: 1.0\n  max_speed: 1.0\n"
      "camera:\n  enabled: false\n";
  struct Case {
    std::string yaml, expect;
  };
  const std::vector<Case> cases = {
      {base + "wind:\n  stedy: [1, 0, 0]\n", "stedy"},                      // typo in a key
      {base + "imu:\n  rate_hz: fast\n", "rate_hz"},                        // wrong type
      {base + "imu:\n  rate_hz: 100\n", "rate_hz"},                         // below 200 Hz
      {"duration: 2.0\n", "trajectory"},                                    // missing section
      {base + "yaw:\n  mode: sideways\n", "mode"},                          // bad choice
      {base + "scene:\n  room_max: [1.2, 5, 3]\n", "outside the room"},     // flight leaves room
      {"duration: 2.0\ntrajectory:\n  type: race\n  gates:\n    - {position: [1, 0, 1]}\n", "gates"},
      {base + "trajectory_extra: 1\n", "trajectory_extra"},
      {"duration: [1\n", ""},                                               // malformed YAML
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path cfg = dir / ("bad" + std::to_string(i) + ".yaml");
    std::ofstream(cfg) << cases[i].yaml;
    const fs::path out = dir / ("out" + std::to_string(i));
    const ToolRun run = runSim("--config " + cfg.string() + " --out " + out.string(), dir);
    EXPECT_EQ(run.code, kExitBadInput) << cases[i].yaml;
    EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find(cases[i].expect), std::string::npos) << "case " << i << ": " << run.err;
    EXPECT_FALSE(fs::exists(out)) << "case " << i;
  }
  const ToolRun missing = runSim("--config " + (dir / "nope.yaml").string() + " --out " + (dir / "o").string(), dir);
  EXPECT_EQ(missing.code, kExitBadInput);
  const ToolRun usage = runSim("--out " + (dir / "o").string(), dir);
  EXPECT_EQ(usage.code, kExitBadInput);
  fs::remove_all(dir);
}

TEST(SimIo, ShippedScenariosAreValid) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(std::string(HDVIO_SOURCE_DIR) + "/config/sim")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const ConfigReader reader = ConfigReader::fromFile(entry.path().string());
    const SimConfig c = loadSimConfig(reader);
    const VehicleModel model(c);  // checks the whole flight is flyable and inside the room
    if (c.trajectory.type != sim::TrajectoryType::kHover) {
      EXPECT_NEAR(model.trajectory().peakSpeed(), c.trajectory.max_speed, 0.01);
    }
    ++count;
  }
  EXPECT_GE(count, 1);
}

}  // namespace
}  // namespace hdvio::sim
