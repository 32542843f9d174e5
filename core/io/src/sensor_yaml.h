#pragma once
// ASL sensor.yaml files (imu0, cam0, rotor0): strict reading with file:line errors, and writing.
#include <string>

#include "hdvio/core/sequence.h"
#include "yaml_fields.h"

namespace hdvio::io {

ImuCalibration readImuSensorYaml(const std::string& path);
CameraCalibration readCameraSensorYaml(const std::string& path);
RotorCalibration readRotorSensorYaml(const std::string& path);
// T_BS (sensor -> body) of a sensor.yaml that carries only its extrinsics, e.g. EuRoC's
// vicon0/sensor.yaml (the motion-capture marker frame).
Pose readSensorExtrinsics(const std::string& path);

std::string imuSensorYaml(const ImuCalibration& calib);
std::string cameraSensorYaml(const CameraCalibration& calib);
std::string rotorSensorYaml(const RotorCalibration& calib);

// resolution, camera_model (pinhole only) and intrinsics [fu fv cu cv] of a camera map (ASL
// sensor.yaml or Kalibr's cam0), shared by both readers.
void readPinhole(const YamlFields& y, CameraCalibration* c);

// Throws InputError unless the calibration is usable (positive intrinsics and size, the right
// number of distortion coefficients for the model, finite values).
void validateCamera(const CameraCalibration& calib, const std::string& file);

const char* distortionName(DistortionModel model);

}  // namespace hdvio::io
