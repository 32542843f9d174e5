#pragma once
// Options shared by every dataset reader.
#include <optional>
#include <string>

namespace hdvio::io {

struct ReadOptions {
  // Largest allowed spacing of consecutive IMU samples; a longer gap is an input error.
  double max_imu_gap_s = 0.05;
  // Check at read time that every image listed in cam0/data.csv exists.
  bool check_images_exist = true;
  // Rotor-speed datasets without a published thrust model (DIDO, NeuroBEM): when given, the
  // reader fills Sequence::rotor_calibration so that thrust = C_T / m * sum(w_i^2) along the
  // thrust axis. Overrides a rotor0/sensor.yaml value for ASL folders.
  std::optional<double> thrust_coefficient;  // N s^2 rad^-2
  std::optional<double> mass;                // kg; default: the dataset's documented mass
  // ROS bags only: the topic-map YAML (empty: EuRoC's topic names) and the calibration: the
  // folder holding cam0/, imu0/ (and rotor0/) sensor.yaml, e.g. an ASL sequence's mav0 folder, or
  // Kalibr files separated by commas (camchain-imucam.yaml,imu.yaml[,rotor0 sensor.yaml]).
  std::string bag_topics;
  std::string calibration;
};

}  // namespace hdvio::io
