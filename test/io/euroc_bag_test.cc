// A EuRoC-style bag of the shared EuRoC excerpt, written by another implementation (Debian's
// python3-rosbag), converts with hdvio_convert to the excerpt's own samples and 95 images.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "../common/run_command.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/io/ros_bag.h"
#include "test_data.h"

namespace hdvio::io {
namespace {

constexpr const char* kPython = "/usr/bin/python3";  // Debian's, which has the rosbag module

std::string writerCommand(const std::string& mav0, const std::string& bag, const std::string& compression) {
  return std::string(kPython) + " " + HDVIO_SOURCE_DIR + "/test/io/write_euroc_bag.py " + mav0 + " " + bag + " " +
         compression;
}

void expectSameFlight(const Sequence& euroc, const Sequence& other) {
  ASSERT_EQ(other.imu.size(), euroc.imu.size());
  for (std::size_t i = 0; i < euroc.imu.size(); ++i) {
    ASSERT_EQ(other.imu[i].t, euroc.imu[i].t) << i;
    ASSERT_EQ(other.imu[i].gyro, euroc.imu[i].gyro) << i;
    ASSERT_EQ(other.imu[i].accel, euroc.imu[i].accel) << i;
  }
  ASSERT_EQ(other.groundtruth.size(), euroc.groundtruth.size());
  for (std::size_t i = 0; i < euroc.groundtruth.size(); ++i) {
    ASSERT_EQ(other.groundtruth[i].t, euroc.groundtruth[i].t) << i;
    ASSERT_EQ(other.groundtruth[i].T_WB.p, euroc.groundtruth[i].T_WB.p) << i;
    ASSERT_EQ(other.groundtruth[i].T_WB.q.coeffs(), euroc.groundtruth[i].T_WB.q.coeffs()) << i;
  }
  ASSERT_EQ(other.images.size(), 95u);
  ASSERT_EQ(euroc.images.size(), 95u);
  for (std::size_t i = 0; i < euroc.images.size(); ++i) {
    ASSERT_EQ(other.images[i].t, euroc.images[i].t) << i;
    ASSERT_EQ(cv::norm(loadImage(other.images[i]), loadImage(euroc.images[i]), cv::NORM_INF), 0.0) << i;
  }
  ASSERT_TRUE(other.camera.has_value());
  EXPECT_EQ(other.camera->fu, euroc.camera->fu);
  EXPECT_EQ(other.camera->distortion_coefficients, euroc.camera->distortion_coefficients);
}

TEST(EurocBag, PythonRosbagWrittenBagConvertsToTheExcerpt) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  if (hdvio::test::runCommand(std::string(kPython) + " -c 'import rosbag, sensor_msgs.msg, geometry_msgs.msg, PIL'").exit_code != 0)
    GTEST_SKIP() << "python3-rosbag, python3-sensor-msgs, python3-geometry-msgs or python3-pil missing "
                    "(scripts/setup.sh installs them)";
  const std::string mav0 = test::dataPath(test::kEuroc) + "/mav0";
  const test::TempDir dir("eurocbag");
  const std::string bag = dir / "V1_01_easy_excerpt.bag";
  const auto w = hdvio::test::runCommand(writerCommand(mav0, bag, "none"));
  ASSERT_EQ(w.exit_code, 0) << w.output;

  const std::string out = dir / "asl";
  const auto c = hdvio::test::runCommand(std::string(HDVIO_CONVERT_BIN) + " --input " + bag + " --calibration " + mav0 +
                                  " --output " + out);  // EuRoC topic names are the defaults: no map
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("1141 IMU"), std::string::npos) << c.output;
  const Sequence euroc = readAsl(mav0);
  expectSameFlight(euroc, readAsl(out));

  // roslz4's chunks (LZ4 frames) read back the same.
  const std::string lz4 = dir / "lz4.bag";
  const auto w4 = hdvio::test::runCommand(writerCommand(mav0, lz4, "lz4"));
  ASSERT_EQ(w4.exit_code, 0) << w4.output;
  ReadOptions o;
  o.calibration = mav0;
  expectSameFlight(euroc, readRosBag(lz4, o));
}

}  // namespace
}  // namespace hdvio::io
