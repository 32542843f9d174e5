// hdvio_run on a ROS bag (images decoded lazily from the bag) gives the result of hdvio_run
// on the ASL folder hdvio_convert makes of that bag: a rendered simulated flight is
// written as a bag by the io tests' bag writer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "../common/run_command.h"
#include "../io/bag_writer.h"
#include "hdvio/core/config.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

// Rows of stamped_traj_estimate.txt: t, p, q.
std::vector<std::array<double, 8>> trajectoryRows(const fs::path& p) {
  std::vector<std::array<double, 8>> rows;
  std::ifstream f(p);
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::array<double, 8> r{};
    for (double& x : r) ss >> x;
    if (ss) rows.push_back(r);
  }
  return rows;
}

TEST(BagRun, BagAndItsConvertedAslFolderGiveTheSameEstimate) {
  const fs::path dir = fs::temp_directory_path() / ("hdvio_bag_run_test_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto config = sim::loadSimConfig(ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_images.yaml"));
  config.duration = 2.0;
  const sim::Simulator simulator(config);
  sim::SimulationResult result = simulator.simulate();
  simulator.renderImages(&result, (dir / "rendered").string());
  const Sequence& seq = result.sequence;
  io::writeAsl(seq, (dir / "calib").string());  // its sensor.yaml files are the bag's calibration

  io::test::BagWriter w("lz4", 256 * 1024);
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  const auto cam = w.connection("/cam0/image_raw", "sensor_msgs/Image");
  const auto thrust = w.connection("/thrust", "geometry_msgs/Vector3Stamped");
  const auto gt = w.connection("/odometry", "nav_msgs/Odometry");
  std::multimap<Timestamp, std::pair<std::uint32_t, std::string>> all;
  for (const auto& s : seq.imu) all.insert({s.t, {imu, io::test::imuMessage(s)}});
  for (const auto& s : seq.thrust) all.insert({s.t, {thrust, io::test::vector3StampedMessage(s)}});
  for (const auto& s : seq.groundtruth)
    all.insert({s.t, {gt, io::test::odometryMessage(s, s.T_WB.q.conjugate() * s.v_W)}});
  for (const auto& image : seq.images)
    all.insert({image.t, {cam, io::test::imageMessage(image.t, io::loadImage(image), "mono8")}});
  for (const auto& [t, m] : all) w.write(m.first, t, m.second);
  const std::string bag = (dir / "flight.bag").string();
  std::ofstream(bag, std::ios::binary) << w.finish();
  fs::remove_all(dir / "rendered");
  std::ofstream(dir / "topics.yaml") << "thrust: /thrust\ngroundtruth: /odometry\n";
  std::ofstream(dir / "vio.yaml") << "method: vimo\nrun: {init_from_groundtruth: true}\n"
                                     "frontend: {source: images, detector: {cell_size: 16}}\n";
  const std::string bag_flags = " --topics " + (dir / "topics.yaml").string() + " --calibration " + (dir / "calib").string();

  auto o = test::runCommand(std::string(HDVIO_CONVERT_BIN) + " --input " + bag + bag_flags + " --output " +
                            (dir / "asl").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const std::string run = std::string(HDVIO_RUN_BINARY) + " --config " + (dir / "vio.yaml").string() + " --evaluate=false";
  // T_BS goes through a 4x4 matrix in sensor.yaml (equal to 1e-14, not bit-exact): the bag run
  // takes its calibration from the converted folder so that both runs read the same files.
  const std::string same_calibration = " --topics " + (dir / "topics.yaml").string() + " --calibration " + (dir / "asl").string();
  o = test::runCommand(run + " --dataset " + bag + same_calibration + " --out " + (dir / "out_bag").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  o = test::runCommand(run + " --dataset " + (dir / "asl").string() + " --out " + (dir / "out_asl").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;

  // hdvio_run is not bit-reproducible: two runs on the same ASL folder differ by ~1e-7 m
  // (measured), so the two estimates must agree to well below what any input difference makes.
  const auto bag_rows = trajectoryRows(dir / "out_bag" / "stamped_traj_estimate.txt");
  const auto asl_rows = trajectoryRows(dir / "out_asl" / "stamped_traj_estimate.txt");
  ASSERT_GT(bag_rows.size(), 20u);
  ASSERT_EQ(bag_rows.size(), asl_rows.size());
  double max_dp = 0.0, max_dq = 0.0;
  for (std::size_t i = 0; i < bag_rows.size(); ++i) {
    ASSERT_EQ(bag_rows[i][0], asl_rows[i][0]) << i;
    for (int k = 1; k < 4; ++k) max_dp = std::max(max_dp, std::abs(bag_rows[i][k] - asl_rows[i][k]));
    for (int k = 4; k < 8; ++k) max_dq = std::max(max_dq, std::abs(bag_rows[i][k] - asl_rows[i][k]));
  }
  std::printf("bag vs converted ASL: max |dp| %.3g m, max |dq| %.3g\n", max_dp, max_dq);
  EXPECT_LT(max_dp, 1e-5);
  EXPECT_LT(max_dq, 1e-6);
  if (!HasFailure()) fs::remove_all(dir);  // kept for inspection otherwise
}

}  // namespace
}  // namespace hdvio
