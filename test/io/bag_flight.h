#pragma once
// The io tests' short flight (every value needs all its bits) as an ASL-ready Sequence and as
// a ROS bag written by bag_writer.h.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bag_writer.h"
#include "hdvio/core/sequence.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io::test {
namespace fs = std::filesystem;

inline constexpr Timestamp kT0 = 1403715273262142976LL;  // a EuRoC-like epoch: seconds above 2^30
inline constexpr int kWidth = 40, kHeight = 30;

// A short flight with values that need every bit (irrational-looking doubles), in the ASL
// layout (images as PNG files under dir) and as the frames themselves.
struct Flight {
  Sequence seq;
  std::vector<cv::Mat> frames;  // BGR
};

inline Flight makeFlight(const fs::path& dir) {
  Flight f;
  Sequence& s = f.seq;
  s.imu_calibration = ImuCalibration{};
  s.imu_calibration->rate_hz = 200.0;
  s.imu_calibration->gyro_noise_density = 1.7e-4;
  s.imu_calibration->accel_noise_density = 2.0e-3;
  s.imu_calibration->gyro_random_walk = 1.9e-5;
  s.imu_calibration->accel_random_walk = 3.0e-3;
  CameraCalibration cam;
  cam.width = kWidth;
  cam.height = kHeight;
  cam.rate_hz = 20.0;
  cam.fu = cam.fv = 45.0;
  cam.cu = 20.0;
  cam.cv = 15.0;
  cam.distortion = DistortionModel::kRadialTangential;
  cam.distortion_coefficients = {-0.28, 0.07, 1.9e-4, 1.8e-5};
  s.camera = cam;
  s.rotor_calibration = RotorCalibration{0.75, 1.9e-6, Vec3::UnitZ()};
  for (int i = 0; i < 200; ++i) {
    const double x = 0.01 * i;
    s.imu.push_back({kT0 + i * 5000000LL + (i % 3), Vec3(std::sin(x) / 3, std::cos(x) / 7, x / 11),
                     Vec3(9.81 + std::sin(3 * x) / 13, std::exp(-x) / 17, -std::sqrt(x + 0.5))});
  }
  for (int i = 0; i < 100; ++i) {
    const double x = 0.02 * i;
    s.rotor.push_back({kT0 + i * 10000000LL + 7, Eigen::Vector4d(1500 + std::sin(x), 1501 / 3.0, 1502 + x / 7, 1499.5)});
    s.thrust.push_back({kT0 + i * 10000000LL + 11, Vec3(0.1 * std::sin(x), 0.2 / 3, 9.81 + x / 9)});
  }
  for (int i = 0; i < 50; ++i) {
    const double x = 0.04 * i;
    GroundTruthState g;
    g.t = kT0 + i * 20000000LL + 3;
    g.T_WB.p = Vec3(std::cos(x), std::sin(x) / 3, 1.0 + x / 7);
    g.T_WB.q = Quat(Eigen::AngleAxisd(0.3 + x / 3, Vec3(1, 2, 3).normalized()));
    s.groundtruth.push_back(g);
  }
  fs::create_directories(dir / "png");
  for (int i = 0; i < 10; ++i) {
    cv::Mat bgr(kHeight, kWidth, CV_8UC3);
    for (int r = 0; r < kHeight; ++r)
      for (int c = 0; c < kWidth; ++c)
        bgr.at<cv::Vec3b>(r, c) = cv::Vec3b((r * 7 + c * 3 + i * 11) % 256, (r * c + i) % 256, (c * 13 + i * 29) % 256);
    cv::Mat gray;
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    const Timestamp t = kT0 + i * 50000000LL + 1;
    const std::string path = (dir / "png" / (std::to_string(t) + ".png")).string();
    cv::imwrite(path, gray);
    s.images.push_back(ImageRef{t, path, std::nullopt, {}, 0});
    f.frames.push_back(bgr);
  }
  return f;
}

inline const char* kTopicMap =
    "imu: /imu0\ncamera: /cam0/image_raw\nrotor_speeds: /rotors\nthrust: /thrust\n"
    "groundtruth: /vicon/firefly_sbx/firefly_sbx\n";

// The flight as a bag, messages interleaved in time order; `encoding`: mono8, bgr8, rgb8 or png.
inline std::string flightBag(const Flight& f, const std::string& compression, const std::string& encoding = "mono8",
                      const std::string& gt_type = "geometry_msgs/PoseStamped") {
  BagWriter w(compression, 4096);
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  const auto cam = w.connection("/cam0/image_raw", encoding == "png" ? "sensor_msgs/CompressedImage" : "sensor_msgs/Image");
  const auto rotor = w.connection("/rotors", "mav_msgs/Actuators");
  const auto thrust = w.connection("/thrust", "geometry_msgs/Vector3Stamped");
  const auto gt = w.connection("/vicon/firefly_sbx/firefly_sbx", gt_type);
  std::multimap<Timestamp, std::pair<std::uint32_t, std::string>> all;
  for (const auto& s : f.seq.imu) all.insert({s.t, {imu, imuMessage(s)}});
  for (const auto& s : f.seq.rotor) all.insert({s.t, {rotor, actuatorsMessage(s)}});
  for (const auto& s : f.seq.thrust) all.insert({s.t, {thrust, vector3StampedMessage(s)}});
  for (const auto& s : f.seq.groundtruth)
    all.insert({s.t, {gt, gt_type == "geometry_msgs/PoseStamped" ? poseStampedMessage(s)
                                                                  : transformStampedMessage(s)}});
  for (std::size_t i = 0; i < f.frames.size(); ++i) {
    const Timestamp t = f.seq.images[i].t;
    cv::Mat px = f.frames[i].clone();  // conversions below must not touch the flight
    std::string msg;
    if (encoding == "png") {
      std::vector<unsigned char> png;
      cv::Mat gray;
      cv::cvtColor(px, gray, cv::COLOR_BGR2GRAY);
      cv::imencode(".png", gray, png);
      msg = compressedImageMessage(t, png);
    } else if (encoding == "mono8") {
      cv::cvtColor(px, px, cv::COLOR_BGR2GRAY);
      msg = imageMessage(t, px, encoding);
    } else {
      if (encoding == "rgb8") cv::cvtColor(px, px, cv::COLOR_BGR2RGB);
      msg = imageMessage(t, px, encoding);
    }
    all.insert({t, {cam, msg}});
  }
  for (const auto& [t, m] : all) w.write(m.first, t + 1000, m.second);  // record time: a little later
  return w.finish();
}

inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The flight under dir as an ASL folder (dir/asl, which is also the bags' calibration) and
// the topic map dir/topics.yaml; `options` reads the flight's bags with both.
struct FlightOnDisk {
  Flight flight;
  ReadOptions options;
};
inline FlightOnDisk writeFlight(const fs::path& dir) {
  FlightOnDisk f{makeFlight(dir), {}};
  writeAsl(f.flight.seq, (dir / "asl").string());
  writeBytes((dir / "topics.yaml").string(), kTopicMap);
  f.options.bag_topics = (dir / "topics.yaml").string();
  f.options.calibration = (dir / "asl/mav0").string();
  return f;
}

}  // namespace hdvio::io::test
