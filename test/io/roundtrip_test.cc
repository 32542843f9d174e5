// Every reader's output written as ASL and read back must give identical samples.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/datasets.h"
#include "hdvio/io/image.h"
#include "hdvio/io/sequence_reader.h"
#include "sequence_compare.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

Sequence roundTrip(const Sequence& in, const test::TempDir& dir, const ReadOptions& options = {}) {
  const std::string out = dir / "asl";
  writeAsl(in, out);
  EXPECT_FALSE(fs::exists(dir.path() / (".asl.partial-" + std::to_string(::getpid()))));
  return readAsl(out, options);
}

TEST(RoundTrip, Blackbird) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdTrain);
  const Sequence in = readSequence(test::dataPath(test::kBlackbirdTrain));
  EXPECT_EQ(detectFormat(test::dataPath(test::kBlackbirdTrain) + "/data.hdf5"), DatasetFormat::kBlackbird);
  ASSERT_EQ(in.imu.size(), 9100u);
  ASSERT_EQ(in.thrust.size(), 9100u);
  ASSERT_EQ(in.groundtruth.size(), 9100u);
  // Timestamps come from the text ground truth with their nanosecond digits.
  EXPECT_EQ(in.imu.front().t, 1525745925001598120LL);
  const test::TempDir dir("bb");
  test::expectSameSamples(in, roundTrip(in, dir));
}

TEST(RoundTrip, DidoFourAndFiveColumnRotorLayouts) {
  for (const char* rel : {test::kDido4Col, test::kDido5Col}) {
    HDVIO_REQUIRE_DATA(rel);
    EXPECT_EQ(detectFormat(test::dataPath(rel)), DatasetFormat::kDido);
    ReadOptions options;
    options.thrust_coefficient = 1.5e-6;
    options.mass = 1.1;
    const Sequence in = readSequence(test::dataPath(rel), options);
    ASSERT_EQ(in.rotor.size(), in.imu.size());
    ASSERT_TRUE(in.rotor_calibration.has_value());
    EXPECT_TRUE(in.hasThrust());
    // rpm / 1e4 -> rad/s: hover speeds of this ~1.1 kg vehicle are ~1500 rad/s in both layouts.
    EXPECT_GT(in.rotor.front().speeds.minCoeff(), 1000.0) << rel;
    EXPECT_LT(in.rotor.front().speeds.maxCoeff(), 2000.0) << rel;
    const test::TempDir dir("dido");
    test::expectSameSamples(in, roundTrip(in, dir));
  }
}

TEST(RoundTrip, DidoRotorSpeedsConvertedFromScaledRpm) {
  HDVIO_REQUIRE_DATA(test::kDido4Col);
  const Sequence in = readDido(test::dataPath(test::kDido4Col));
  // First meas_rpm row: 1.4191 1.5333 1.4344 1.598 (rpm / 1e4).
  EXPECT_NEAR(in.rotor.front().speeds[0], 1.4191e4 * 2 * M_PI / 60, 1e-9);
  EXPECT_NEAR(in.rotor.front().speeds[3], 1.5980e4 * 2 * M_PI / 60, 1e-9);
  EXPECT_FALSE(in.rotor_calibration.has_value());  // no thrust model unless given
  EXPECT_FALSE(in.hasThrust());
}

TEST(RoundTrip, NeuroBem) {
  HDVIO_REQUIRE_DATA(test::kNeuroBem);
  const Sequence in = readSequence(test::dataPath(test::kNeuroBem));
  ASSERT_EQ(in.imu.size(), 14306u);
  EXPECT_EQ(in.imu.front().t, 9330000000LL);
  EXPECT_EQ(in.imu[1].t, 9332500000LL);
  const test::TempDir dir("nb");
  test::expectSameSamples(in, roundTrip(in, dir));

  const auto forces = readNeuroBemForces(test::dataPath(test::kNeuroBem));
  ASSERT_EQ(forces.size(), in.imu.size());
  EXPECT_EQ(forces.front().t, in.imu.front().t);
  EXPECT_EQ(forces.front().force.z(), 7.539003);
  // The model's hover force is about mass * specific force: 0.772 kg * 9.74 m/s^2.
  EXPECT_NEAR(forces.front().force.z(), kNeuroBemMass * in.imu.front().accel.z(), 0.2);
}

TEST(RoundTrip, EurocCopiesImages) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  const Sequence in = readAsl(test::dataPath(test::kEuroc));
  const test::TempDir dir("euroc");
  const Sequence back = roundTrip(in, dir);
  test::expectSameSamples(in, back);
  ASSERT_EQ(back.images.size(), 95u);
  EXPECT_EQ(fs::path(back.images[3].path).parent_path(), fs::path(dir / "asl/mav0/cam0/data"));
  EXPECT_EQ(fs::file_size(back.images[3].path), fs::file_size(in.images[3].path));
  const cv::Mat a = loadImage(in.images[3]), b = loadImage(back.images[3]);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

// The simulator's use: PNGs already written into out/mav0/cam0/data, everything else from memory.
TEST(RoundTrip, SyntheticSequenceWithForcesLandmarksAndImagesInPlace) {
  const test::TempDir dir("synthetic");
  const std::string out = dir / "sim";
  fs::create_directories(out + "/mav0/cam0/data");
  Sequence seq;
  seq.name = "sim";
  CameraCalibration cam;
  cam.width = 64;
  cam.height = 48;
  cam.rate_hz = 10;
  cam.fu = cam.fv = 50.123456789012345;
  cam.cu = 32.5;
  cam.cv = 24.25;
  cam.distortion = DistortionModel::kEquidistant;
  cam.distortion_coefficients = {0.1, -0.01, 1e-3, -1e-4};
  cam.T_BS = Pose(quatExp(Vec3(0.1, -0.2, 0.3)), Vec3(0.01, 0.02, -0.03));
  seq.camera = cam;
  seq.imu_calibration = ImuCalibration{Pose(), 400.0, 1e-4, 2e-5, 3e-3, 4e-4};
  seq.rotor_calibration = RotorCalibration{0.8, 2.5e-6, Vec3::UnitZ()};
  for (int k = 0; k < 400; ++k) {
    const Timestamp t = 1000000000LL + k * 2500000LL;
    const double s = k * 0.01;
    seq.imu.push_back({t, Vec3(std::sin(s), 1.0 / 3.0, -s), Vec3(0.1 * s, std::cos(s), 9.81 + 1e-17 * k)});
    seq.thrust.push_back({t, Vec3(0, 0, 9.81 + std::sin(s))});
    seq.rotor.push_back({t, Eigen::Vector4d(1000 + s, 1001, 1002, 1003.0 / 7.0)});
    GroundTruthState g;
    g.t = t;
    g.T_WB = Pose(quatExp(Vec3(0.01 * s, -0.2, std::sqrt(2.0) * s)), Vec3(s, 2 * s, 1.0 / 7.0));
    g.v_W = Vec3(1, 2, 3) * s;
    g.has_velocity = true;
    g.gyro_bias = Vec3(1e-3, -2e-3, 3e-3);
    g.accel_bias = Vec3(0.01, 0.02, -0.03) * s;
    g.has_biases = true;
    seq.groundtruth.push_back(g);
    seq.forces.push_back({t, Vec3(0.1, -0.2, 0.3) * s, Vec3(-0.05, 0.0, 0.01) * s});
    if (k % 40 == 0) {
      const std::string png = out + "/mav0/cam0/data/frame_" + std::to_string(k) + ".png";
      cv::imwrite(png, cv::Mat(48, 64, CV_8UC1, cv::Scalar(k % 256)));
      seq.images.push_back({t, png, "", 0});
      for (int id = 0; id < 3; ++id) seq.landmark_observations.push_back({t, id, 10.5 + id + s, 20.25 - s});
    }
  }
  for (int id = 0; id < 3; ++id) seq.landmarks[id] = Vec3(id, 1.0 / (id + 3.0), -2.0);

  writeAsl(seq, out);
  const Sequence back = readAsl(out);
  test::expectSameSamples(seq, back);
  // In-place images keep their names and are not duplicated.
  EXPECT_EQ(fs::path(back.images[1].path).filename(), "frame_40.png");
  int files = 0;
  for (const auto& e : fs::directory_iterator(out + "/mav0/cam0/data")) files += e.is_regular_file();
  EXPECT_EQ(files, 10);
  EXPECT_EQ(loadImage(back.images[2]).at<unsigned char>(5, 5), 80);
  EXPECT_TRUE(back.warnings.empty());
}

TEST(RoundTrip, GroundTruthWithoutBiasesKeepsItsLayout) {
  const test::TempDir dir("gt11");
  Sequence seq;
  for (int k = 0; k < 5; ++k) {
    seq.imu.push_back({k * 5000000LL, Vec3::Zero(), Vec3(0, 0, 9.81)});
    GroundTruthState g;
    g.t = k * 5000000LL;
    g.v_W = Vec3(k, 0, 0);
    g.has_velocity = true;
    seq.groundtruth.push_back(g);
  }
  const Sequence back = roundTrip(seq, dir);
  test::expectSameSamples(seq, back);
  EXPECT_FALSE(back.groundtruth[0].has_biases);
  EXPECT_FALSE(back.camera.has_value());
}

TEST(WriteAsl, RejectsInconsistentSequencesWithoutPartialOutput) {
  const test::TempDir dir("reject");
  Sequence seq;
  EXPECT_THROW(writeAsl(seq, dir / "empty"), InputError);  // no IMU
  seq.imu.push_back({0, Vec3::Zero(), Vec3(0, 0, 9.81)});
  seq.images.push_back({0, dir / "missing.png", "", 0});
  EXPECT_THROW(writeAsl(seq, dir / "nocam"), InputError);  // images without calibration
  seq.camera = CameraCalibration{Pose(), 10, 10, 10.0, 5, 5, 5, 5, DistortionModel::kNone, {}, ""};
  EXPECT_THROW(writeAsl(seq, dir / "noimage"), InputError);  // image file missing
  EXPECT_TRUE(fs::is_empty(dir.path()));  // nothing written, staging folders removed
}

}  // namespace
}  // namespace hdvio::io
