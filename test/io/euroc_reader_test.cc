// The real EuRoC V1_01_easy excerpt, read through the ASL reader and the dispatcher.
#include <gtest/gtest.h>

#include <filesystem>

#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/io/sequence_info.h"
#include "hdvio/io/sequence_reader.h"
#include "test_data.h"

namespace hdvio::io {
namespace {

TEST(EurocExcerpt, CountsRatesAndSpans) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  const Sequence seq = readSequence(test::dataPath(test::kEuroc));
  EXPECT_EQ(detectFormat(test::dataPath(test::kEuroc)), DatasetFormat::kAsl);
  EXPECT_EQ(seq.name, "V1_01_easy_excerpt");
  EXPECT_EQ(seq.images.size(), 95u);
  EXPECT_EQ(seq.imu.size(), 1141u);
  EXPECT_EQ(seq.groundtruth.size(), 115u);
  EXPECT_TRUE(seq.thrust.empty());
  EXPECT_TRUE(seq.warnings.empty());
  EXPECT_EQ(seq.imu.front().t, 1403715273262142976LL);
  EXPECT_EQ(seq.images.back().t, 1403715277962142976LL);

  const SequenceSummary s = summarize(seq);
  EXPECT_NEAR(s.duration_s, 4.7, 1e-6);
  ASSERT_GE(s.streams.size(), 3u);
  EXPECT_EQ(s.streams[0].name, "imu0");
  EXPECT_NEAR(s.streams[0].rate_hz, 200.0, 0.1);
  EXPECT_EQ(s.streams[1].name, "cam0");
  EXPECT_NEAR(s.streams[1].rate_hz, 20.0, 0.01);
  EXPECT_NEAR(s.groundtruth_coverage, 1.0, 1e-9);
  for (const auto& m : s.methods) {
    const bool expected = m.method == "vio" || m.method == "tlio" || m.method == "evaluation";
    EXPECT_EQ(m.supported, expected) << m.method;
  }
}

TEST(EurocExcerpt, CalibrationValues) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  const Sequence seq = readAsl(test::dataPath(test::kEuroc) + "/mav0");  // mav0 itself works too
  ASSERT_TRUE(seq.camera.has_value());
  const CameraCalibration& c = *seq.camera;
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.rate_hz, 20.0);
  EXPECT_EQ(c.fu, 458.654);
  EXPECT_EQ(c.fv, 457.296);
  EXPECT_EQ(c.cu, 367.215);
  EXPECT_EQ(c.cv, 248.375);
  EXPECT_EQ(c.distortion, DistortionModel::kRadialTangential);
  ASSERT_EQ(c.distortion_coefficients.size(), 4u);
  EXPECT_EQ(c.distortion_coefficients[0], -0.28340811);
  EXPECT_EQ(c.distortion_coefficients[3], 1.76187114e-05);
  const Mat4 T = c.T_BS.matrix();
  EXPECT_NEAR(T(0, 1), -0.999880929698, 1e-9);
  EXPECT_NEAR(T(1, 3), -0.064676986768, 1e-12);
  EXPECT_NEAR(T(2, 2), 0.999660727178, 1e-9);

  ASSERT_TRUE(seq.imu_calibration.has_value());
  EXPECT_EQ(seq.imu_calibration->rate_hz, 200.0);
  EXPECT_EQ(seq.imu_calibration->gyro_noise_density, 1.6968e-04);
  EXPECT_EQ(seq.imu_calibration->accel_random_walk, 3.0e-3);
  EXPECT_TRUE(seq.imu_calibration->T_BS.matrix().isIdentity(1e-15));
}

TEST(EurocExcerpt, GroundTruthAndImages) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  const Sequence seq = readAsl(test::dataPath(test::kEuroc));
  const GroundTruthState& g = seq.groundtruth.front();
  EXPECT_TRUE(g.has_velocity);
  EXPECT_TRUE(g.has_biases);
  EXPECT_EQ(g.T_WB.p.x(), 0.878895);
  // q_RS is (w, x, y, z) = (0.069433, -0.824237, -0.106942, -0.551702), normalized.
  const Quat q = Quat(0.069433, -0.824237, -0.106942, -0.551702).normalized();
  EXPECT_NEAR(g.T_WB.q.angularDistance(q), 0.0, 1e-12);
  EXPECT_NEAR(g.accel_bias.z(), 0.0309774, 1e-15);
  EXPECT_TRUE(std::filesystem::path(seq.images.front().path).is_absolute());
  const cv::Mat image = loadImage(seq.images.front());
  EXPECT_EQ(image.cols, 752);
  EXPECT_EQ(image.rows, 480);
  EXPECT_EQ(image.type(), CV_8UC1);
}

}  // namespace
}  // namespace hdvio::io
