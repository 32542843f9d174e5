// Writes small valid seed inputs for every fuzz target into <out>/<target>/, with the
// project's own writers (writeAsl, the tests' BagWriter, formatTcnFile, libhdf5). With a
// second argument, the EuRoC excerpt's files (first rows) become seeds too. scripts/fuzz.sh
// runs it into build-fuzz/ at run time; nothing it writes goes into the repository.
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bag_writer.h"
#include "hdf5_dataset_writer.h"
#include "fuzz_common.h"
#include "hdvio/io/asl.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace fs = std::filesystem;
using namespace hdvio;

namespace {

fs::path out_root;
int written = 0;

void seed(const std::string& target, const std::string& name, const std::string& bytes) {
  fuzz::writeFile(out_root / target / name, bytes);
  ++written;
}

std::string readFile(const fs::path& p, std::size_t max_lines = 1u << 30) {
  std::ifstream in(p, std::ios::binary);
  std::string out, line;
  for (std::size_t i = 0; i < max_lines && std::getline(in, line); ++i) out += line + "\n";
  return out;
}

Sequence syntheticSequence() {
  Sequence s;
  for (int i = 0; i < 8; ++i) {
    const Timestamp t = 1000000000LL + i * 5000000LL;
    s.imu.push_back(ImuSample{t, Vec3(0.01 * i, 0.02, -0.03), Vec3(0.1, -0.2, 9.81)});
    s.thrust.push_back(ThrustSample{t, Vec3(0, 0, 9.7 + 0.01 * i)});
    RotorSample r;
    r.t = t;
    r.speeds = Eigen::Vector4d(1000 + i, 1001, 1002, 1003);
    s.rotor.push_back(r);
    GroundTruthState g;
    g.t = t;
    g.T_WB.p = Vec3(0.1 * i, 0.2, 1.0);
    g.v_W = Vec3(1, 0, 0);
    g.has_velocity = true;
    g.has_biases = i % 2 == 0;
    s.groundtruth.push_back(g);
    s.forces.push_back(ForceSample{t, Vec3(0.1, 0, 0), Vec3(0, 0.1, 0)});
  }
  s.rotor_calibration = RotorCalibration{0.8, 1.5e-6, Vec3::UnitZ()};
  s.landmarks = {{0, Vec3(1, 2, 3)}, {7, Vec3(4, 5, 6)}};
  s.landmark_observations = {{1000000000LL, 0, 100.5, 200.25}, {1005000000LL, 7, 50, 60}};
  return s;
}

// mode bytes of fuzz_asl_csv: the index of the file in its kTargets table.
void aslSeeds(const fs::path& euroc) {
  const std::vector<std::pair<int, std::string>> files = {
      {1, "imu0/data.csv"}, {2, "cam0/data.csv"}, {3, "state_groundtruth_estimate0/data.csv"},
      {4, "thrust0/data.csv"}, {5, "rotor0/data.csv"}, {6, "force_groundtruth0/data.csv"},
      {7, "landmarks0/data.csv"}, {8, "landmarks0/points.csv"}};
  const fs::path tmp = out_root / "tmp_asl";
  fs::remove_all(tmp);
  io::writeAsl(syntheticSequence(), tmp.string());
  for (const auto& [mode, rel] : files) {
    const fs::path p = tmp / "mav0" / rel;
    if (fs::exists(p)) seed("fuzz_asl_csv", "synthetic_" + std::to_string(mode), std::string(1, char(mode)) + readFile(p));
    if (!euroc.empty() && fs::exists(euroc / "mav0" / rel))
      seed("fuzz_asl_csv", "euroc_" + std::to_string(mode), std::string(1, char(mode)) + readFile(euroc / "mav0" / rel, 20));
  }
  // mode 0: CsvReader alone, ',' (even high bits) and ' ' (odd) delimiters.
  seed("fuzz_asl_csv", "text_blank", std::string(1, char(9)) +
       "# ts x y z qx qy qz qw vx vy vz\n1525745925.001598119736 1 2 3 0 0 0 1 0.1 0.2 0.3\n"
       "1525745925.011598119736 1 2 3 0 0 0 1 0.1 0.2 0.3\n1.5e9 -1 -2 -3 0 0 0.7071 0.7071 0 0 0\n");
  seed("fuzz_asl_csv", "text_comma", std::string(1, char(0)) + "#t,a,b\n1,2.5,-3e4\n-7, 1 ,0x10\n");
  for (const char* yaml : {"imu0/sensor.yaml", "rotor0/sensor.yaml"}) {
    const fs::path p = tmp / "mav0" / yaml;
    if (fs::exists(p)) seed("fuzz_sensor_yaml", std::string(yaml).substr(0, 6), std::string(1, yaml[0] == 'i' ? 0 : 2) + readFile(p));
  }
  fs::remove_all(tmp);
}

void yamlSeeds(const fs::path& euroc) {
  seed("fuzz_sensor_yaml", "imu", std::string(1, 0) + fuzz::kImuYaml);
  seed("fuzz_sensor_yaml", "camera", std::string(1, 1) + fuzz::kCameraYaml);
  seed("fuzz_sensor_yaml", "topics", std::string(1, 3) +
       "imu: /imu0\ncamera: /cam0/image_raw\nrotor_speeds: /rotors\nthrust: /thrust\n"
       "thrust_axis: [0, 0, 1]\ngroundtruth: /vicon\n");
  seed("fuzz_sensor_yaml", "kalibr_camchain", std::string(1, 4) +
       "cam0:\n  cam_overlaps: []\n  camera_model: pinhole\n  distortion_coeffs: [-0.28, 0.07, 0.0002, 1.8e-05]\n"
       "  distortion_model: radtan\n  intrinsics: [458.654, 457.296, 367.215, 248.375]\n  resolution: [752, 480]\n"
       "  rostopic: /cam0/image_raw\n  timeshift_cam_imu: -8.1e-05\n  T_cam_imu:\n"
       "  - [0.0148655, 0.9995572, -0.0257744, 0.0652229]\n  - [-0.9998809, 0.0149672, 0.0037561, -0.0207064]\n"
       "  - [0.0041403, 0.0257155, 0.9996608, -0.0080546]\n  - [0.0, 0.0, 0.0, 1.0]\n");
  seed("fuzz_sensor_yaml", "kalibr_imu", std::string(1, 4) +
       "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
       "gyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 1.9e-5\nrostopic: /imu0\nupdate_rate: 200.0\n");
  seed("fuzz_sensor_yaml", "kalibr_imu0", std::string(1, 4) +
       "imu0:\n  T_i_b:\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n"
       "  - [0.0, 0.0, 0.0, 1.0]\n  accelerometer_noise_density: 2.0e-3\n  accelerometer_random_walk: 3.0e-3\n"
       "  gyroscope_noise_density: 1.7e-4\n  gyroscope_random_walk: 1.9e-5\n  model: calibrated\n"
       "  rostopic: /imu0\n  time_offset: 0.0\n  update_rate: 200.0\n");
  if (euroc.empty()) return;
  for (auto [mode, rel] : {std::pair<int, const char*>{0, "imu0/sensor.yaml"}, {1, "cam0/sensor.yaml"}}) {
    if (fs::exists(euroc / "mav0" / rel))
      seed("fuzz_sensor_yaml", "euroc_" + std::to_string(mode), std::string(1, char(mode)) + readFile(euroc / "mav0" / rel));
  }
}

// Every message type hdvio reads, for both the bag and the message target.
void bagSeeds() {
  using namespace io::test;
  const Sequence s = syntheticSequence();
  cv::Mat pixels(6, 8, CV_8UC1);
  for (int r = 0; r < pixels.rows; ++r)
    for (int c = 0; c < pixels.cols; ++c) pixels.at<unsigned char>(r, c) = static_cast<unsigned char>(r * 30 + c);
  cv::Mat color;
  cv::cvtColor(pixels, color, cv::COLOR_GRAY2BGR);
  std::vector<unsigned char> png;
  cv::imencode(".png", pixels, png);
  const Vec3 v_body(1, 0, 0);
  const std::vector<std::pair<int, std::string>> messages = {
      {0, imuMessage(s.imu[0])}, {1, actuatorsMessage(s.rotor[0])}, {2, vector3StampedMessage(s.thrust[0])},
      {3, agirosCommandMessage(s.imu[0].t, 9.8)}, {4, poseStampedMessage(s.groundtruth[0])},
      {5, transformStampedMessage(s.groundtruth[0])}, {6, odometryMessage(s.groundtruth[0], v_body)},
      {7, imageMessage(s.imu[0].t, pixels, "mono8")}, {8, imageMessage(s.imu[0].t, color, "bgr8")},
      {9, compressedImageMessage(s.imu[0].t, png)}};
  for (const auto& [mode, bytes] : messages)
    seed("fuzz_ros_messages", "type_" + std::to_string(mode), std::string(1, char(mode)) + bytes);

  for (const char* compression : {"none", "bz2", "lz4"}) {
    BagWriter w(compression, 600);
    const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
    const auto cam = w.connection("/cam0/image_raw", "sensor_msgs/Image");
    const auto gt = w.connection("/vicon/firefly_sbx/firefly_sbx", "geometry_msgs/TransformStamped");
    for (std::size_t i = 0; i < 4; ++i) {
      w.write(imu, s.imu[i].t, imuMessage(s.imu[i]));
      w.write(gt, s.groundtruth[i].t, transformStampedMessage(s.groundtruth[i]));
    }
    w.write(cam, s.imu[0].t, imageMessage(s.imu[0].t, pixels, "mono8"));
    seed("fuzz_ros_bag", std::string("euroc_topics_") + compression, w.finish());
  }
  BagWriter w("none", 100000);
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  const auto cam = w.connection("/cam0/image_raw", "sensor_msgs/CompressedImage");
  const auto gt = w.connection("/vicon/firefly_sbx/firefly_sbx", "nav_msgs/Odometry");
  for (std::size_t i = 0; i < 3; ++i) {
    w.write(imu, s.imu[i].t, imuMessage(s.imu[i]));
    w.write(gt, s.groundtruth[i].t, odometryMessage(s.groundtruth[i], v_body));
  }
  w.write(cam, s.imu[0].t, compressedImageMessage(s.imu[0].t, png));
  seed("fuzz_ros_bag", "compressed_image_odometry", w.finish());
}

void hdf5Seeds() {
  const std::size_t n = 6;
  std::vector<double> ts, v3, rpm, q;
  for (std::size_t i = 0; i < n; ++i) {
    ts.push_back(1.5e9 + 0.01 * i);
    for (int k = 0; k < 3; ++k) v3.push_back(0.1 * k + i);
    for (int k = 0; k < 4; ++k) rpm.push_back(1.0 + k);
    q.insert(q.end(), {1.0, 0.0, 0.0, 0.0});
  }
  for (bool dido : {false, true}) {
    const std::string path = (out_root / "tmp.hdf5").string();
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    io::test::writeDataset(f, "ts", ts, 1);
    for (const char* name : dido ? std::vector<const char*>{"gyr", "acc", "gt_p", "gt_v"}
                                 : std::vector<const char*>{"gyro_calib", "accel_calib", "thrust"})
      io::test::writeDataset(f, name, v3, 3);
    if (dido) {
      io::test::writeDataset(f, "meas_rpm", rpm, 4);
      io::test::writeDataset(f, "gt_q", q, 4);
    }
    H5Fclose(f);
    seed("fuzz_hdf5_raw", dido ? "dido" : "blackbird", readFile(path));
    fs::remove(path);
  }
  // fuzz_hdf5_datasets reads a recipe, not a file: a few fixed pseudo-random recipes long
  // enough to describe several datasets start it past libFuzzer's short first inputs.
  std::uint32_t state = 12345;
  for (int k = 0; k < 8; ++k) {
    std::string recipe(256 << (k % 4), '\0');
    for (char& c : recipe) c = static_cast<char>((state = state * 1664525u + 1013904223u) >> 24);
    seed("fuzz_hdf5_datasets", "recipe_" + std::to_string(k), recipe);
  }
}

learned::Tcn smallTcn(bool residual, bool variance_head) {
  learned::TcnArchitecture a;
  a.input_channels = 2;
  a.kernel_size = 2;
  a.window = 8;
  a.residual = residual;
  a.variance_head = variance_head;
  a.layers = {{3, 1}, {2, 2}};
  learned::TcnWeights w;
  float x = 0.125f;
  auto fill = [&](long r, long c) {
    learned::MatrixXf m(r, c);
    for (long i = 0; i < m.size(); ++i) {
      x += 0.37f;
      m.data()[i] = x - std::floor(x) - 0.5f;
    }
    return m;
  };
  w.input_mean = fill(2, 1);
  w.input_std = learned::VectorXf::Constant(2, 1.5f);
  long width = 2;
  for (const auto& l : a.layers) {
    for (int j = 0; j < (residual ? 2 : 1); ++j) {
      const long in = j == 0 ? width : l.out_channels;
      w.conv.push_back({fill(l.out_channels, a.kernel_size * in), fill(l.out_channels, 1)});
    }
    if (residual) {
      learned::TcnConvWeights sk;
      if (width != l.out_channels) sk = {fill(l.out_channels, width), fill(l.out_channels, 1)};
      w.skip.push_back(sk);
    }
    width = l.out_channels;
  }
  w.head_weight = fill(3, width);
  w.head_bias = fill(3, 1);
  if (variance_head) {
    w.logvar_weight = fill(3, width);
    w.logvar_bias = fill(3, 1);
  }
  return learned::Tcn(a, w);
}

void tcnSeeds() {
  seed("fuzz_tcn_weights", "v1", learned::formatTcnWeights(smallTcn(false, true), "seed"));
  learned::TcnFileInfo info;
  info.task = "displacement";
  info.inputs = "accel_gyro";
  info.output_sigma = {0.1, 0.2, 0.3};
  seed("fuzz_tcn_weights", "v2_text", learned::formatTcnFile(smallTcn(true, false), info));
  seed("fuzz_tcn_weights", "v2_float32",
       learned::formatTcnFile(smallTcn(true, true), info, "", learned::TcnEncoding::kFloat32));
  learned::TcnFileInfo drag;
  drag.drag_law.linear = Vec3(0.3, 0.3, 0.1);
  drag.drag_law.quadratic = Vec3(0.01, 0.01, 0.0);
  seed("fuzz_tcn_weights", "v3", learned::formatTcnFile(smallTcn(false, false), drag));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: fuzz_make_seeds <out folder> [<EuRoC ASL folder>]\n";
    return 2;
  }
  out_root = argv[1];
  const fs::path euroc = argc > 2 && fs::is_directory(argv[2]) ? fs::path(argv[2]) : fs::path();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  aslSeeds(euroc);
  yamlSeeds(euroc);
  bagSeeds();
  hdf5Seeds();
  tcnSeeds();
  std::cout << "wrote " << written << " seeds into " << out_root.string() << "\n";
  return 0;
}
