// ROS 1 bags written by the tests' own writer read back equal to the ASL path, for every chunk
// compression and message type hdvio reads; hdvio_convert turns them into the same ASL folder.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../common/run_command.h"
#include "bag_flight.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/csv.h"
#include "hdvio/io/image.h"
#include "hdvio/io/ros_bag.h"
#include "hdvio/io/sequence_reader.h"
#include "sequence_compare.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

using test::Flight;
using test::kT0;
using test::writeBytes;

void expectSamePixels(const Sequence& a, const Sequence& b) {
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) {
    const cv::Mat x = loadImage(a.images[i]), y = loadImage(b.images[i]);
    ASSERT_EQ(x.size(), y.size()) << i;
    ASSERT_EQ(cv::norm(x, y, cv::NORM_INF), 0.0) << "image " << i;
  }
}

class RosBag : public ::testing::Test {
 protected:
  void SetUp() override {
    const test::FlightOnDisk f = test::writeFlight(dir_.path());
    flight_ = f.flight;
    options_ = f.options;
    asl_ = readAsl(dir_ / "asl");
  }
  ReadOptions bagOptions() const { return options_; }
  test::TempDir dir_{"bag"};
  Flight flight_;
  ReadOptions options_;
  Sequence asl_;
};

TEST_F(RosBag, EveryCompressionReadsBackEqualToTheAslFolder) {
  for (const char* compression : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    const std::string bag = dir_ / (std::string(compression) + ".bag");
    writeBytes(bag, test::flightBag(flight_, compression));
    EXPECT_EQ(detectFormat(bag), DatasetFormat::kRosBag);
    const Sequence seq = readSequence(bag, bagOptions());
    test::expectSameSamples(asl_, seq);
    expectSamePixels(asl_, seq);
    ASSERT_TRUE(seq.camera && seq.imu_calibration && seq.rotor_calibration);
    EXPECT_EQ(seq.camera->distortion_coefficients, asl_.camera->distortion_coefficients);
    EXPECT_EQ(seq.imu_calibration->gyro_noise_density, asl_.imu_calibration->gyro_noise_density);
    EXPECT_TRUE(seq.images.front().span.has_value()) << "images stay in the bag";
    EXPECT_EQ(seq.name, compression);
  }
}

TEST_F(RosBag, ColorRawAndCompressedImagesBecomeTheSameGrayscale) {
  for (const char* encoding : {"bgr8", "rgb8", "png"}) {
    SCOPED_TRACE(encoding);
    const std::string bag = dir_ / (std::string(encoding) + ".bag");
    writeBytes(bag, test::flightBag(flight_, "lz4", encoding));
    const Sequence seq = readRosBag(bag, bagOptions());
    expectSamePixels(asl_, seq);
  }
}

TEST_F(RosBag, TransformStampedAndOdometryGroundTruth) {
  const std::string bag = dir_ / "tf.bag";
  writeBytes(bag, test::flightBag(flight_, "none", "mono8", "geometry_msgs/TransformStamped"));
  test::expectSameSamples(asl_, readRosBag(bag, bagOptions()));

  // nav_msgs/Odometry: twist in the body (child) frame, rotated into the world.
  test::BagWriter w;
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  const auto odom = w.connection("/odom", "nav_msgs/Odometry");
  for (const auto& s : flight_.seq.imu) w.write(imu, s.t, test::imuMessage(s));
  const GroundTruthState& g = flight_.seq.groundtruth[5];
  w.write(odom, g.t, test::odometryMessage(g, Vec3(1.0, -2.0, 0.5)));
  writeBytes(dir_ / "odom.bag", w.finish());
  writeBytes(dir_ / "odom.yaml", "groundtruth: /odom\n");
  ReadOptions o;
  o.bag_topics = dir_ / "odom.yaml";
  const Sequence seq = readRosBag(dir_ / "odom.bag", o);
  ASSERT_EQ(seq.groundtruth.size(), 1u);
  EXPECT_TRUE(seq.groundtruth[0].has_velocity);
  EXPECT_LT((seq.groundtruth[0].v_W - g.T_WB.q * Vec3(1.0, -2.0, 0.5)).norm(), 1e-12);
  EXPECT_EQ(seq.groundtruth[0].T_WB.p, g.T_WB.p);
  EXPECT_FALSE(seq.camera.has_value()) << "no images, no calibration needed";
}

// EuRoC's Vicon topic is the marker, not the body: with vicon0/sensor.yaml (T_BS: marker ->
// body) in the calibration folder the ground truth becomes the body pose again.
TEST_F(RosBag, ViconSensorYamlMovesGroundTruthFromTheMarkerToTheBody) {
  const Pose T_BS(Quat(Eigen::AngleAxisd(1.9, Vec3(0.3, -1.0, 0.2).normalized())), Vec3(0.069, -0.028, -0.124));
  test::Flight marker = flight_;
  for (GroundTruthState& g : marker.seq.groundtruth) g.T_WB = g.T_WB * T_BS;  // what the Vicon sees
  const std::string bag = dir_ / "marker.bag";
  writeBytes(bag, test::flightBag(marker, "none", "mono8", "geometry_msgs/TransformStamped"));
  const Sequence raw = readRosBag(bag, bagOptions());
  ASSERT_EQ(raw.groundtruth.size(), asl_.groundtruth.size());
  EXPECT_GT((raw.groundtruth[7].T_WB.p - asl_.groundtruth[7].T_WB.p).norm(), 0.1) << "without it: the marker";

  const Mat4 M = T_BS.matrix();
  std::string data;
  for (int i = 0; i < 16; ++i) data += (i ? ", " : "") + formatDouble(M(i / 4, i % 4));
  fs::create_directories(dir_ / "asl/mav0/vicon0");
  writeBytes(dir_ / "asl/mav0/vicon0/sensor.yaml", "%YAML:1.0\nsensor_type: vicon\ncomment: VICON motion capture system\n"
                                                   "T_BS:\n  cols: 4\n  rows: 4\n  data: [" + data + "]\n");
  const Sequence body = readRosBag(bag, bagOptions());
  fs::remove_all(dir_ / "asl/mav0/vicon0");
  ASSERT_EQ(body.groundtruth.size(), asl_.groundtruth.size());
  for (std::size_t i = 0; i < body.groundtruth.size(); ++i) {
    EXPECT_LT((body.groundtruth[i].T_WB.p - asl_.groundtruth[i].T_WB.p).norm(), 1e-9) << i;
    EXPECT_LT(body.groundtruth[i].T_WB.q.angularDistance(asl_.groundtruth[i].T_WB.q), 1e-9) << i;
  }
  bool warned = false;
  for (const std::string& w : body.warnings) warned = warned || w.find("marker to the body") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST_F(RosBag, AgirosCollectiveThrustAlongTheMappedAxis) {
  test::BagWriter w;
  const auto imu = w.connection("/camera/imu", "sensor_msgs/Imu");
  const auto cmd = w.connection("/parrot/agiros_pilot/mpc_command", "agiros_msgs/Command");
  for (const auto& s : flight_.seq.imu) w.write(imu, s.t, test::imuMessage(s));
  w.write(cmd, kT0 + 10, test::agirosCommandMessage(kT0 + 10, 9.5));
  w.write(cmd, kT0 + 20, test::agirosCommandMessage(kT0 + 20, 10.25));
  writeBytes(dir_ / "agi.bag", w.finish());
  writeBytes(dir_ / "agi.yaml",
             "imu: /camera/imu\ncamera: ''\nthrust: /parrot/agiros_pilot/mpc_command\nthrust_axis: [0, -1, 0]\n");
  ReadOptions o;
  o.bag_topics = dir_ / "agi.yaml";
  const Sequence seq = readRosBag(dir_ / "agi.bag", o);
  ASSERT_EQ(seq.thrust.size(), 2u);
  EXPECT_EQ(seq.thrust[1].t, kT0 + 20);
  EXPECT_EQ(seq.thrust[1].thrust, Vec3(0.0, -10.25, 0.0));
  ASSERT_EQ(seq.imu.size(), asl_.imu.size());
  EXPECT_EQ(seq.imu.back().accel, asl_.imu.back().accel);
}

TEST_F(RosBag, MessagesAreOrderedByRecordTimeAcrossChunks) {
  // The IMU written in two halves, the later half first (in earlier chunks of the file).
  test::BagWriter w("bz2", 1024);
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  const auto& s = flight_.seq.imu;
  for (std::size_t i = s.size() / 2; i < s.size(); ++i) w.write(imu, s[i].t, test::imuMessage(s[i]));
  for (std::size_t i = 0; i < s.size() / 2; ++i) w.write(imu, s[i].t, test::imuMessage(s[i]));
  writeBytes(dir_ / "shuffled.bag", w.finish());
  const Sequence seq = readRosBag(dir_ / "shuffled.bag");
  ASSERT_EQ(seq.imu.size(), s.size());
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(seq.imu[i].t, s[i].t) << i;
}

TEST_F(RosBag, ConvertWritesTheSameAslFolder) {
  const std::string bag = dir_ / "flight.bag";
  writeBytes(bag, test::flightBag(flight_, "lz4"));
  const std::string out = dir_ / "converted";
  const auto o = hdvio::test::runCommand(std::string(HDVIO_CONVERT_BIN) + " --input " + bag + " --topics " +
                                         (dir_ / "topics.yaml") + " --calibration " + (dir_ / "asl/mav0") +
                                         " --output " + out);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const Sequence back = readAsl(out);
  test::expectSameSamples(asl_, back);
  expectSamePixels(asl_, back);
  EXPECT_FALSE(back.images.front().span.has_value());

  const auto info = hdvio::test::runCommand(std::string(HDVIO_INFO_BIN) + " " + bag + " --topics " +
                                            (dir_ / "topics.yaml") + " --calibration " + (dir_ / "asl/mav0"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("format:   rosbag"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("imu0"), std::string::npos) << info.output;
}

}  // namespace
}  // namespace hdvio::io
