#include "hdvio/run/imo_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "hdvio/core/error.h"

namespace hdvio::run {
Vec3 readVec3(const ConfigReader& r, const std::string& key, const Vec3& fallback) {
  std::vector<double> v{fallback.x(), fallback.y(), fallback.z()};
  r.readVector(key, &v, 3);
  return Vec3(v[0], v[1], v[2]);
}

void readImoFilterSection(const ConfigReader& f, const std::string& config_path,
                          ImoFilterSection* section) {
  imo::ImoRunOptions& run = *section->options;
  imo::ImoFilterOptions& o = run.filter;
  f.readInRange("gyro_noise_density", &o.gyro_noise_density, 0.0, 10.0);
  f.readInRange("accel_noise_density", &o.accel_noise_density, 0.0, 100.0);
  f.readInRange("gyro_random_walk", &o.gyro_random_walk, 0.0, 10.0);
  f.readInRange("accel_random_walk", &o.accel_random_walk, 0.0, 100.0);
  double att_deg = o.init_attitude_sigma * 180.0 / M_PI, yaw_deg = o.init_yaw_sigma * 180.0 / M_PI;
  f.readInRange("init_attitude_sigma_deg", &att_deg, 0.0, 180.0);
  f.readInRange("init_yaw_sigma_deg", &yaw_deg, 0.0, 180.0);
  o.init_attitude_sigma = att_deg * M_PI / 180.0;
  o.init_yaw_sigma = yaw_deg * M_PI / 180.0;
  f.readInRange("init_velocity_sigma", &o.init_velocity_sigma, 0.0, 100.0);
  f.readInRange("init_position_sigma", &o.init_position_sigma, 0.0, 1000.0);
  f.readInRange("init_gyro_bias_sigma", &o.init_gyro_bias_sigma, 0.0, 10.0);
  f.readInRange("init_accel_bias_sigma", &o.init_accel_bias_sigma, 0.0, 100.0);
  f.readInRange("mahalanobis_factor", &o.mahalanobis_factor, -1.0, 1e6);
  section->init_gyro_bias = readVec3(f, "init_gyro_bias", section->init_gyro_bias);
  section->init_accel_bias = readVec3(f, "init_accel_bias", section->init_accel_bias);
  f.readInRange("update_rate_hz", &run.update_rate_hz, 1.0, 1000.0);
  run.measurement_sigma = readVec3(f, "measurement_sigma", run.measurement_sigma);
  if (!(run.measurement_sigma.array() > 0.0).all())
    throw InputError(config_path, 0, "filter.measurement_sigma must be positive");
  f.readOptional("use_source_covariance", &run.use_source_covariance);
  f.readOptional("release_propagation", &o.release_propagation);
  f.readOptional("initial_window_biases", &run.initial_window_biases);
  std::string rotation_error = "right";
  f.readChoice("rotation_error", &rotation_error, {"right", "left"});
  o.rotation_error = rotation_error == "left" ? imo::RotationError::kLeft : imo::RotationError::kRight;
  double g = -o.gravity.z();
  f.readInRange("gravity", &g, 9.7, 9.9);
  o.gravity = Vec3(0.0, 0.0, -g);
  f.readOptional("release_first_window_sample", &section->release_first_window_sample);
  f.finish();
}

std::shared_ptr<const learned::DisplacementModel> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights_out) {
  std::string weights;
  network.read("weights", &weights);
  network.finish();
  if (weights_out) *weights_out = weights;
  const std::filesystem::path w(weights);
  const std::string path = w.is_absolute() || experiment_dir.empty()
                               ? weights
                               : (std::filesystem::path(experiment_dir) / w).string();
  return std::make_shared<const learned::DisplacementModel>(learned::DisplacementModel::load(path));
}

std::vector<ImuSample> imuSpanWithGroundTruth(const Sequence& seq, double start_offset_s,
                                              double duration_s) {
  if (seq.groundtruth.empty()) throw InputError(seq.source, 0, "the sequence has no ground truth");
  const Timestamp t_gt = seq.groundtruth.front().t + fromSeconds(start_offset_s);
  auto first = std::lower_bound(seq.imu.begin(), seq.imu.end(), t_gt,
                                [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (first == seq.imu.end() || first->t > seq.groundtruth.back().t)
    throw InputError(seq.source, 0, "no IMU sample inside the ground-truth span");
  auto last = seq.imu.end();
  if (duration_s > 0.0)
    last = std::upper_bound(first, seq.imu.end(), first->t + fromSeconds(duration_s),
                            [](Timestamp t, const ImuSample& s) { return t < s.t; });
  return std::vector<ImuSample>(first, last);
}

}  // namespace hdvio::run
