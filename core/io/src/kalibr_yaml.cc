#include "kalibr_yaml.h"

#include <cmath>

#include "hdvio/core/error.h"
#include "sensor_yaml.h"
#include "yaml_fields.h"

namespace hdvio::io {
namespace {

void readCamera(const YamlFields& file, KalibrCalibration* out) {
  const YamlFields y = file.child("cam0");
  y.rejectUnknownKeys({"camera_model", "intrinsics", "distortion_model", "distortion_coeffs", "resolution",
                       "rostopic", "T_cam_imu", "T_imu_cam", "timeshift_cam_imu", "cam_overlaps"});
  CameraCalibration c;
  c.file = y.path();
  readPinhole(y, &c);
  const std::string model = y.text("distortion_model");
  if (model == "radtan") {
    c.distortion = DistortionModel::kRadialTangential;
  } else if (model == "equidistant") {
    c.distortion = DistortionModel::kEquidistant;
  } else if (model == "none") {
    c.distortion = DistortionModel::kNone;
  } else {
    y.fail(y.node("distortion_model"), "distortion_model",
           "unsupported '" + model + "' (expected radtan, equidistant or none)");
  }
  if (c.distortion != DistortionModel::kNone || y.has("distortion_coeffs"))
    c.distortion_coefficients = y.numbers("distortion_coeffs", c.distortion == DistortionModel::kNone ? -1 : 4);
  if (c.distortion == DistortionModel::kNone && !c.distortion_coefficients.empty() &&
      c.distortion_coefficients.size() != 4)
    y.fail(y.node("distortion_coeffs"), "distortion_coeffs", "expected 4 values or none");
  if (y.has("T_cam_imu") && y.has("T_imu_cam"))
    y.fail(y.node("T_imu_cam"), "T_imu_cam", "give T_cam_imu (Kalibr) or T_imu_cam (OpenVINS), not both");
  if (y.has("T_cam_imu")) {
    c.T_BS = y.transformRows("T_cam_imu").inverse();
  } else if (y.has("T_imu_cam")) {
    c.T_BS = y.transformRows("T_imu_cam");
  } else {
    throw InputError(y.path(), y.node("camera_model").Mark().line + 1,
                     "cam0 has no camera-IMU extrinsics (T_cam_imu): pass the camchain-imucam yaml written by "
                     "kalibr_calibrate_imu_camera");
  }
  if (y.has("timeshift_cam_imu")) {
    out->timeshift_cam_imu = y.number("timeshift_cam_imu");
    // Kalibr's estimates are milliseconds; a larger value is a wrong file (and would overflow ns).
    if (std::abs(out->timeshift_cam_imu) > 1.0)
      y.fail(y.node("timeshift_cam_imu"), "timeshift_cam_imu", "must be within +-1 s");
  }
  out->camera = c;
  if (file.has("cam1")) out->warnings.push_back(y.path() + ": only cam0 is used (the pipelines are monocular)");
}

void readImu(const YamlFields& file, KalibrCalibration* out) {
  const bool nested = file.has("imu0");
  const YamlFields y = nested ? file.child("imu0") : file;
  y.rejectUnknownKeys({"accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density",
                       "gyroscope_random_walk", "update_rate", "rostopic", "T_i_b", "model", "time_offset"});
  if (nested && file.has("imu1")) out->warnings.push_back(y.path() + ": only imu0 is used");
  if (y.has("model") && y.text("model") != "calibrated")
    y.fail(y.node("model"), "model", "unsupported '" + y.text("model") + "' (expected calibrated)");
  if (y.has("time_offset") && y.number("time_offset") != 0.0)
    y.fail(y.node("time_offset"), "time_offset", "imu0's time offset must be 0 (it is the reference clock)");
  ImuCalibration c;
  if (y.has("T_i_b")) c.T_BS = y.transformRows("T_i_b").inverse();
  c.rate_hz = y.number("update_rate");
  if (c.rate_hz <= 0.0) y.fail(y.node("update_rate"), "update_rate", "must be positive");
  c.gyro_noise_density = y.number("gyroscope_noise_density");
  c.gyro_random_walk = y.number("gyroscope_random_walk");
  c.accel_noise_density = y.number("accelerometer_noise_density");
  c.accel_random_walk = y.number("accelerometer_random_walk");
  for (const char* key : {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                          "accelerometer_random_walk"}) {
    if (y.number(key) < 0.0) y.fail(y.node(key), key, "must not be negative");
  }
  out->imu = c;
}

}  // namespace

void readKalibrYaml(const std::string& path, KalibrCalibration* out) {
  const YamlFields y(path);
  // Kalibr has no rotor model: a rotor-speed bag adds the ASL rotor0/sensor.yaml to the list.
  if (y.has("sensor_type") && y.text("sensor_type") == "rotor") {
    if (out->rotor) throw InputError(path, 0, "a second rotor calibration (one is enough)");
    out->rotor = readRotorSensorYaml(path);
    return;
  }
  if (y.has("sensor_type") && y.text("sensor_type") == "vicon") {
    if (out->groundtruth_T_BS) throw InputError(path, 0, "a second vicon0/sensor.yaml (one is enough)");
    out->groundtruth_T_BS = readSensorExtrinsics(path);
    return;
  }
  if (y.has("sensor_type") || y.has("T_BS"))
    throw InputError(path, 0, "an ASL sensor.yaml, not a Kalibr file: pass the folder holding cam0/ and imu0/");
  if (y.has("cam0")) {
    if (out->camera) throw InputError(path, 0, "a second Kalibr camchain (one is enough)");
    readCamera(y, out);
  } else if (y.has("imu0") || y.has("accelerometer_noise_density")) {
    if (out->imu) throw InputError(path, 0, "a second Kalibr IMU file (one is enough)");
    readImu(y, out);
  } else {
    throw InputError(path, 0, "neither a Kalibr camchain (cam0:) nor a Kalibr IMU file (accelerometer_noise_density)");
  }
}

}  // namespace hdvio::io
