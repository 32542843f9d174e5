#pragma once
// Kalibr's calibration files as a bag's calibration: the camchain written by
// kalibr_calibrate_imu_camera (cam0 with T_cam_imu and timeshift_cam_imu) and the IMU noise file
// (Kalibr's imu.yaml, or the imu0: map of its imu-*.yaml output). OpenVINS's copies of them
// (T_imu_cam instead of T_cam_imu) read too. Only cam0 is used (the pipelines are monocular).
#include <optional>
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::io {

struct KalibrCalibration {
  std::optional<CameraCalibration> camera;  // T_BS: camera -> IMU; rate_hz 0 (camchains carry none)
  double timeshift_cam_imu = 0.0;           // [s], t_imu = t_cam + timeshift_cam_imu
  std::optional<ImuCalibration> imu;        // T_BS: IMU -> body (inverse of T_i_b, identity if absent)
  std::optional<RotorCalibration> rotor;    // from an ASL rotor0/sensor.yaml in the list
  std::optional<Pose> groundtruth_T_BS;     // from an ASL vicon0/sensor.yaml in the list
  std::vector<std::string> warnings;
};

// Reads one file into out: a camchain (a top-level cam0 map), an IMU file, or an ASL
// rotor0/ or vicon0/sensor.yaml (Kalibr has neither a rotor model nor the mocap marker). Throws InputError
// naming the file and line for anything else, unknown keys, unsupported models, a second
// camchain or IMU file.
void readKalibrYaml(const std::string& path, KalibrCalibration* out);

}  // namespace hdvio::io
