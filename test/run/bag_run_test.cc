// hdvio_run on a ROS bag (images decoded lazily from the bag) gives exactly the result of
// hdvio_run on the ASL folder hdvio_convert makes of that bag: a rendered simulated flight is
// written as a bag by the io tests' bag writer.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

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

std::string fileText(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
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
  o = test::runCommand(run + " --dataset " + bag + bag_flags + " --out " + (dir / "out_bag").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  o = test::runCommand(run + " --dataset " + (dir / "asl").string() + " --out " + (dir / "out_asl").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;

  for (const char* f : {"stamped_traj_estimate.txt", "stamped_velocity_estimate.csv", "stamped_bias_estimate.csv"}) {
    const std::string a = fileText(dir / "out_bag" / f), b = fileText(dir / "out_asl" / f);
    EXPECT_GT(std::count(a.begin(), a.end(), '\n'), 20) << f;
    EXPECT_EQ(a, b) << f;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hdvio
