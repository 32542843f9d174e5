#include "sensor_yaml.h"

#include <cmath>

#include "hdvio/core/error.h"
#include "hdvio/io/csv.h"
#include "yaml_fields.h"

namespace hdvio::io {
namespace {

std::string matrixYaml(const Pose& T) {
  const Mat4 M = T.matrix();
  std::string s = "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int i = 0; i < 16; ++i) {
    s += formatDouble(M(i / 4, i % 4));
    s += i == 15 ? "]\n" : (i % 4 == 3 ? ",\n         " : ", ");
  }
  return s;
}

std::string list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + formatDouble(v[i]);
  return s + "]";
}

}  // namespace

const char* distortionName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kRadialTangential: return "radial-tangential";
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: break;
  }
  return "none";
}

void readPinhole(const YamlFields& y, CameraCalibration* c) {
  const std::vector<double> res = y.numbers("resolution", 2);
  // Checked before the cast: a double beyond int's range does not convert.
  for (double r : res) {
    if (!(r >= 1.0 && r <= 1e6 && r == std::floor(r)))
      y.fail(y.node("resolution"), "resolution", "expected two positive integers");
  }
  c->width = static_cast<int>(res[0]);
  c->height = static_cast<int>(res[1]);
  const std::string camera_model = y.text("camera_model");
  if (camera_model != "pinhole")
    y.fail(y.node("camera_model"), "camera_model", "unsupported '" + camera_model + "' (expected pinhole)");
  const std::vector<double> k = y.numbers("intrinsics", 4);
  c->fu = k[0];
  c->fv = k[1];
  c->cu = k[2];
  c->cv = k[3];
  if (c->fu <= 0 || c->fv <= 0 || c->cu <= 0 || c->cv <= 0)
    y.fail(y.node("intrinsics"), "intrinsics", "fu, fv, cu, cv must be positive");
}

ImuCalibration readImuSensorYaml(const std::string& path) {
  const YamlFields y(path);
  ImuCalibration c;
  c.T_BS = y.transform("T_BS");
  c.rate_hz = y.number("rate_hz");
  c.gyro_noise_density = y.number("gyroscope_noise_density");
  c.gyro_random_walk = y.number("gyroscope_random_walk");
  c.accel_noise_density = y.number("accelerometer_noise_density");
  c.accel_random_walk = y.number("accelerometer_random_walk");
  if (c.rate_hz <= 0.0) y.fail(y.node("rate_hz"), "rate_hz", "must be positive");
  for (const char* key : {"gyroscope_noise_density", "gyroscope_random_walk",
                          "accelerometer_noise_density", "accelerometer_random_walk"}) {
    if (y.number(key) < 0.0) y.fail(y.node(key), key, "must not be negative");
  }
  return c;
}

CameraCalibration readCameraSensorYaml(const std::string& path) {
  const YamlFields y(path);
  CameraCalibration c;
  c.file = path;
  c.T_BS = y.transform("T_BS");
  c.rate_hz = y.number("rate_hz");
  readPinhole(y, &c);
  if (c.rate_hz <= 0.0) y.fail(y.node("rate_hz"), "rate_hz", "must be positive");

  const std::string model = y.has("distortion_model") ? y.text("distortion_model") : "none";
  int expected = 0;
  if (model == "radial-tangential" || model == "radtan") {
    c.distortion = DistortionModel::kRadialTangential;
    expected = 4;
  } else if (model == "equidistant" || model == "equi") {
    c.distortion = DistortionModel::kEquidistant;
    expected = 4;
  } else if (model == "none") {
    c.distortion = DistortionModel::kNone;
  } else {
    y.fail(y.node("distortion_model"), "distortion_model",
           "unknown model '" + model + "' (expected radial-tangential, equidistant or none)");
  }
  if (expected > 0 || y.has("distortion_coefficients")) {
    c.distortion_coefficients = y.numbers("distortion_coefficients", expected);
  }
  return c;
}

RotorCalibration readRotorSensorYaml(const std::string& path) {
  const YamlFields y(path);
  RotorCalibration c;
  c.mass = y.number("mass");
  c.thrust_coefficient = y.number("thrust_coefficient");
  const std::vector<double> axis = y.numbers("thrust_axis", 3);
  c.thrust_axis = Vec3(axis[0], axis[1], axis[2]);
  if (c.mass <= 0.0) y.fail(y.node("mass"), "mass", "must be positive");
  if (c.thrust_coefficient <= 0.0)
    y.fail(y.node("thrust_coefficient"), "thrust_coefficient", "must be positive");
  if (std::fabs(c.thrust_axis.norm() - 1.0) > 1e-6)
    y.fail(y.node("thrust_axis"), "thrust_axis", "must be a unit vector");
  return c;
}

Pose readSensorExtrinsics(const std::string& path) { return YamlFields(path).transform("T_BS"); }

void validateCamera(const CameraCalibration& c, const std::string& file) {
  if (c.width <= 0 || c.height <= 0) throw InputError(file, 0, "camera resolution must be positive");
  if (!(c.fu > 0 && c.fv > 0 && c.cu > 0 && c.cv > 0))
    throw InputError(file, 0, "camera intrinsics must be positive");
  const std::size_t expected = c.distortion == DistortionModel::kNone ? 0 : 4;
  if (c.distortion_coefficients.size() != expected &&
      !(c.distortion == DistortionModel::kNone && c.distortion_coefficients.size() == 4)) {
    throw InputError(file, 0, std::string("distortion model ") + distortionName(c.distortion) +
                                  " needs " + std::to_string(expected) + " coefficients, got " +
                                  std::to_string(c.distortion_coefficients.size()));
  }
}

std::string imuSensorYaml(const ImuCalibration& c) {
  return "%YAML:1.0\n# Written by hdvio\nsensor_type: imu\n" + matrixYaml(c.T_BS) +
         "rate_hz: " + formatDouble(c.rate_hz) + "\n" +
         "gyroscope_noise_density: " + formatDouble(c.gyro_noise_density) + "\n" +
         "gyroscope_random_walk: " + formatDouble(c.gyro_random_walk) + "\n" +
         "accelerometer_noise_density: " + formatDouble(c.accel_noise_density) + "\n" +
         "accelerometer_random_walk: " + formatDouble(c.accel_random_walk) + "\n";
}

std::string cameraSensorYaml(const CameraCalibration& c) {
  return "%YAML:1.0\n# Written by hdvio\nsensor_type: camera\n" + matrixYaml(c.T_BS) +
         "rate_hz: " + formatDouble(c.rate_hz) + "\n" +
         "resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n" +
         "camera_model: pinhole\n" +
         "intrinsics: " + list({c.fu, c.fv, c.cu, c.cv}) + "  # fu, fv, cu, cv\n" +
         "distortion_model: " + distortionName(c.distortion) + "\n" +
         "distortion_coefficients: " + list(c.distortion_coefficients) + "\n";
}

std::string rotorSensorYaml(const RotorCalibration& c) {
  return "%YAML:1.0\n# Written by hdvio: thrust = thrust_coefficient / mass * sum(w_i^2) * thrust_axis\n"
         "sensor_type: rotor\n"
         "mass: " + formatDouble(c.mass) + "  # [kg]\n" +
         "thrust_coefficient: " + formatDouble(c.thrust_coefficient) + "  # [N s^2 rad^-2]\n" +
         "thrust_axis: " + list({c.thrust_axis.x(), c.thrust_axis.y(), c.thrust_axis.z()}) +
         "  # IMU frame\n";
}

}  // namespace hdvio::io
