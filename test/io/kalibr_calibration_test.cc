// Kalibr's camchain-imucam.yaml and imu.yaml as a bag's calibration: the same sequence as the ASL
// sensor.yaml files holding the same numbers, with Kalibr's conventions (T_cam_imu is IMU ->
// camera, t_imu = t_cam + timeshift_cam_imu) and OpenVINS's variant (T_imu_cam, imu0: with T_i_b).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "../common/run_command.h"
#include "bag_flight.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/sequence_reader.h"
#include "sequence_compare.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

std::string rows(const Pose& T) {
  const Mat4 M = T.matrix();
  std::ostringstream s;
  s.precision(17);
  for (int r = 0; r < 4; ++r) s << "  - [" << M(r, 0) << ", " << M(r, 1) << ", " << M(r, 2) << ", " << M(r, 3) << "]\n";
  return s.str();
}

std::string camchain(const CameraCalibration& c, const std::string& extrinsics_key, const Pose& T,
                     const std::string& extra = "") {
  std::ostringstream s;
  s.precision(17);
  s << "cam0:\n  camera_model: pinhole\n  intrinsics: [" << c.fu << ", " << c.fv << ", " << c.cu << ", " << c.cv
    << "]\n  distortion_model: radtan\n  distortion_coeffs: [" << c.distortion_coefficients[0] << ", "
    << c.distortion_coefficients[1] << ", " << c.distortion_coefficients[2] << ", " << c.distortion_coefficients[3]
    << "]\n  resolution: [" << c.width << ", " << c.height << "]\n  rostopic: /cam0/image_raw\n  cam_overlaps: []\n  "
    << extrinsics_key << ":\n" << rows(T) << extra;
  return s.str();
}

std::string imuYaml(const ImuCalibration& c) {
  std::ostringstream s;
  s.precision(17);
  s << "#Accelerometers\naccelerometer_noise_density: " << c.accel_noise_density
    << "\naccelerometer_random_walk: " << c.accel_random_walk << "\n#Gyroscopes\ngyroscope_noise_density: "
    << c.gyro_noise_density << "\ngyroscope_random_walk: " << c.gyro_random_walk
    << "\nrostopic: /imu0\nupdate_rate: " << c.rate_hz << "\n";
  return s.str();
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

void expectNear(const Pose& a, const Pose& b, double tol) {
  EXPECT_LE((a.p - b.p).norm(), tol);
  EXPECT_LE(a.q.angularDistance(b.q), tol);
}

class KalibrCalibration : public ::testing::Test {
 protected:
  void SetUp() override {
    // The test flight with EuRoC's cam0 extrinsics, so that T_cam_imu is not the identity.
    flight_ = test::makeFlight(dir_.path());
    flight_.seq.camera->T_BS = readAsl(test::dataPath(test::kEuroc)).camera->T_BS;
    ASSERT_GT(flight_.seq.camera->T_BS.p.norm(), 0.05);
    writeAsl(flight_.seq, dir_ / "asl");
    test::writeBytes(dir_ / "topics.yaml", test::kTopicMap);
    bag_ = dir_ / "flight.bag";
    test::writeBytes(bag_, test::flightBag(flight_, "lz4"));
    options_.bag_topics = dir_ / "topics.yaml";
    options_.calibration = dir_ / "asl/mav0";
    asl_ = readSequence(bag_, options_);
    camchain_ = dir_ / "camchain-imucam.yaml";
    imu_ = dir_ / "imu.yaml";
    write(imu_, imuYaml(*flight_.seq.imu_calibration));
  }
  Sequence withKalibr(const std::string& files) const {
    ReadOptions o = options_;
    o.calibration = files;
    return readSequence(bag_, o);
  }
  test::TempDir dir_{"kalibr"};
  test::Flight flight_;
  std::string bag_, camchain_, imu_;
  ReadOptions options_;
  Sequence asl_;
};

TEST_F(KalibrCalibration, CamchainAndImuFileGiveTheAslCalibration) {
  const CameraCalibration& c = *flight_.seq.camera;
  write(camchain_, camchain(c, "T_cam_imu", c.T_BS.inverse()));
  const std::string rotor = dir_ / "asl/mav0/rotor0/sensor.yaml";  // Kalibr has no rotor model
  for (const std::string& files : {camchain_ + "," + imu_ + "," + rotor, rotor + "," + imu_ + "," + camchain_}) {
    SCOPED_TRACE(files);
    const Sequence k = withKalibr(files);
    test::expectSameSamples(asl_, k);
    ASSERT_TRUE(k.camera && k.imu_calibration);
    expectNear(k.camera->T_BS, asl_.camera->T_BS, 1e-12);
    expectNear(k.imu_calibration->T_BS, Pose(), 0.0);
    EXPECT_EQ(k.camera->fu, c.fu);
    EXPECT_EQ(k.camera->cv, c.cv);
    EXPECT_EQ(k.camera->width, c.width);
    EXPECT_EQ(k.camera->distortion, DistortionModel::kRadialTangential);
    EXPECT_EQ(k.camera->distortion_coefficients, c.distortion_coefficients);
    EXPECT_NEAR(k.camera->rate_hz, 20.0, 1e-9) << "from the image stamps: camchains carry no rate";
    EXPECT_EQ(k.imu_calibration->rate_hz, 200.0);
    EXPECT_EQ(k.imu_calibration->gyro_noise_density, asl_.imu_calibration->gyro_noise_density);
    EXPECT_EQ(k.imu_calibration->accel_random_walk, asl_.imu_calibration->accel_random_walk);
  }
}

TEST_F(KalibrCalibration, OpenVinsVariantComposesTheBodyFrame) {
  // OpenVINS's copies: T_imu_cam (camera -> IMU) and an imu0: map whose T_i_b is body -> IMU.
  const CameraCalibration& c = *flight_.seq.camera;
  const Pose T_i_b(Quat(Eigen::AngleAxisd(0.2, Vec3(0, 0, 1))), Vec3(0.01, -0.02, 0.03));
  write(camchain_, camchain(c, "T_imu_cam", c.T_BS));
  std::string imu = "imu0:\n  T_i_b:\n" + rows(T_i_b) + "  model: calibrated\n  time_offset: 0.0\n";
  std::istringstream flat(imuYaml(*flight_.seq.imu_calibration));
  for (std::string line; std::getline(flat, line);)
    if (line[0] != '#') imu += "  " + line + "\n";
  write(imu_, imu);
  const Sequence k = withKalibr(camchain_ + "," + imu_);
  expectNear(k.imu_calibration->T_BS, T_i_b.inverse(), 1e-12);
  expectNear(k.camera->T_BS, T_i_b.inverse() * c.T_BS, 1e-12);
}

TEST_F(KalibrCalibration, TimeshiftMovesImageStampsToTheImuClock) {
  const CameraCalibration& c = *flight_.seq.camera;
  write(camchain_, camchain(c, "T_cam_imu", c.T_BS.inverse(), "  timeshift_cam_imu: 0.0025\n"));
  const Sequence k = withKalibr(camchain_ + "," + imu_);
  ASSERT_EQ(k.images.size(), asl_.images.size());
  for (std::size_t i = 0; i < k.images.size(); ++i) EXPECT_EQ(k.images[i].t, asl_.images[i].t + 2500000) << i;
  ASSERT_EQ(k.imu.size(), asl_.imu.size());
  EXPECT_EQ(k.imu.front().t, asl_.imu.front().t);
  bool warned = false;
  for (const std::string& w : k.warnings) warned = warned || w.find("timeshift_cam_imu") != std::string::npos;
  EXPECT_TRUE(warned);
}

void expectInputError(const std::function<void()>& read, const std::string& file, long line,
                      const std::string& words) {
  try {
    read();
    ADD_FAILURE() << "accepted; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(e.problem().find(words), std::string::npos) << e.what();
  }
}

TEST_F(KalibrCalibration, BadFilesNameTheFileAndLine) {
  const CameraCalibration& c = *flight_.seq.camera;
  const std::string good = camchain(c, "T_cam_imu", c.T_BS.inverse());
  const std::string both = camchain_ + "," + imu_;
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  write(camchain_, replaced("camera_model: pinhole", "camera_model: omni"));
  expectInputError([&] { withKalibr(both); }, camchain_, 2, "unsupported 'omni'");
  write(camchain_, replaced("  rostopic", "  line_delay: 1e-5\n  rostopic"));
  expectInputError([&] { withKalibr(both); }, camchain_, 7, "unknown key 'line_delay'");
  write(camchain_, replaced("distortion_model: radtan", "distortion_model: fov"));
  expectInputError([&] { withKalibr(both); }, camchain_, 4, "unsupported 'fov'");
  write(camchain_, good + "  timeshift_cam_imu: 1e300\n");
  expectInputError([&] { withKalibr(both); }, camchain_, 14, "within +-1 s");
  write(camchain_, good.substr(0, good.find("  T_cam_imu")));
  expectInputError([&] { withKalibr(both); }, camchain_, 2, "no camera-IMU extrinsics");
  write(camchain_, replaced("- [0, 0, 0, 1]", "- [0, 0, 1, 1]"));
  expectInputError([&] { withKalibr(both); }, camchain_, 10, "last row");
  write(camchain_, good);
  expectInputError([&] { withKalibr(camchain_); }, camchain_, 0, "no Kalibr IMU file");
  expectInputError([&] { withKalibr(imu_); }, imu_, 0, "no Kalibr camchain");
  expectInputError([&] { withKalibr(both + "," + camchain_); }, camchain_, 0, "a second Kalibr camchain");
  expectInputError([&] { withKalibr(camchain_ + "," + dir_ / "nope.yaml"); }, dir_ / "nope.yaml", 0, "does not exist");
  const std::string sensor = dir_ / "asl/mav0/imu0/sensor.yaml";
  expectInputError([&] { withKalibr(camchain_ + "," + sensor); }, sensor, 0, "ASL sensor.yaml");
}

TEST_F(KalibrCalibration, ConvertWritesAReadableAslFolder) {
  const CameraCalibration& c = *flight_.seq.camera;
  write(camchain_, camchain(c, "T_cam_imu", c.T_BS.inverse()));
  const std::string out = dir_ / "converted";
  const auto o = hdvio::test::runCommand(std::string(HDVIO_CONVERT_BIN) + " --input " + bag_ + " --topics " +
                                  (dir_ / "topics.yaml") + " --calibration " + camchain_ + "," + imu_ + "," +
                                  (dir_ / "asl/mav0/rotor0/sensor.yaml") + " --output " + out);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const Sequence converted = readAsl(out);
  test::expectSameSamples(asl_, converted);
  expectNear(converted.camera->T_BS, asl_.camera->T_BS, 1e-12);
  EXPECT_NEAR(converted.camera->rate_hz, 20.0, 1e-9);
}

}  // namespace
}  // namespace hdvio::io
