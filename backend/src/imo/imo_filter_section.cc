#include "hdvio/backend/imo/imo_filter_section.h"

#include <cmath>

#include "hdvio/core/error.h"

namespace hdvio {

Vec3 readVec3(const ConfigReader& r, const std::string& key, const Vec3& fallback) {
  std::vector<double> v{fallback.x(), fallback.y(), fallback.z()};
  r.readVector(key, &v, 3);
  return Vec3(v[0], v[1], v[2]);
}

namespace imo {

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

}  // namespace imo
}  // namespace hdvio
