#include "hdvio/backend/vio_options.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "hdvio/core/error.h"

namespace hdvio {

VioMethod parseVioMethod(const std::string& name) {
  if (name == "vio") return VioMethod::kVio;
  if (name == "vimo") return VioMethod::kVimo;
  if (name == "vid") return VioMethod::kVid;
  if (name == "hdvio") return VioMethod::kHdvio;
  throw std::invalid_argument("unknown visual-inertial method '" + name + "'");
}

std::string toString(VioMethod method) {
  switch (method) {
    case VioMethod::kVio: return "vio";
    case VioMethod::kVimo: return "vimo";
    case VioMethod::kVid: return "vid";
    case VioMethod::kHdvio: return "hdvio";
  }
  return "?";
}

namespace {
void readVec3(const ConfigReader& c, const std::string& key, Vec3* v, bool positive) {
  std::vector<double> x{v->x(), v->y(), v->z()};
  c.readVector(key, &x, 3);
  for (double xi : x)
    if (xi < 0.0 || (positive && xi == 0.0))
      throw InputError(c.file(), 0, "key '" + (c.path().empty() ? key : c.path() + "." + key) +
                                        "': values must be " + (positive ? "positive" : "non-negative"));
  *v = Vec3(x[0], x[1], x[2]);
}
}  // namespace

namespace {
// The envelope keys bound nothing unless given (or adopted from the model's weight file).
void readModelEnvelope(const ConfigReader& c, ModelEnvelope* e) {
  if (c.has("model_speed_max")) c.readInRange("model_speed_max", &e->speed_max, 1e-3, 1e3);
  if (c.has("model_rate_max")) c.readInRange("model_rate_max", &e->rate_max, 1e-3, 1e3);
  if (c.has("model_thrust_range")) {
    std::vector<double> range;
    c.readVector("model_thrust_range", &range, 2);
    if (!(range[0] >= 0.0 && range[1] > range[0]))
      throw InputError(c.file(), 0,
                       "key '" + (c.path().empty() ? std::string("") : c.path() + ".") +
                           "model_thrust_range': needs 0 <= min < max");
    e->thrust_min = range[0];
    e->thrust_max = range[1];
  }
}

void finalize(VioBackendOptions* o) {
  o->thrust.gyro_noise_density = o->imu.gyro_noise_density;
  o->thrust.gyro_random_walk = o->imu.gyro_random_walk;
}
}  // namespace

VioBackendOptions defaultVioBackendOptions(VioMethod method) {
  VioBackendOptions o;
  o.method = method;
  finalize(&o);
  return o;
}

VioBackendOptions loadVioBackendOptions(const ConfigReader& c, VioMethod method) {
  VioBackendOptions o;
  o.method = method;
  c.readInRange("num_keyframes", &o.num_keyframes, 2, 100);
  c.readInRange("num_recent", &o.num_recent, 1, 100);
  c.readInRange("keyframe_parallax_px", &o.keyframe_parallax_px, 0.0, 1000.0);
  c.readInRange("keyframe_min_tracked_ratio", &o.keyframe_min_tracked_ratio, 0.0, 1.0);
  c.readInRange("pixel_sigma", &o.pixel_sigma, 1e-3, 100.0);
  c.readEnum("robust_loss", &o.robust_loss,
             {{"none", RobustLoss::kNone}, {"huber", RobustLoss::kHuber}});
  c.readInRange("robust_width_px", &o.robust_width_px, 1e-3, 100.0);
  c.readInRange("outlier_threshold_px", &o.outlier_threshold_px, 0.1, 1000.0);
  c.readInRange("min_triangulation_angle_deg", &o.min_triangulation_angle_deg, 0.0, 45.0);
  c.readInRange("max_landmarks", &o.max_landmarks, 1, 100000);
  c.readEnum("landmark_marginalization", &o.landmark_marginalization,
             {{"all", LandmarkMarginalization::kAll},
              {"keyframes", LandmarkMarginalization::kKeyframes},
              {"untracked", LandmarkMarginalization::kUntracked}});
  c.readInRange("max_iterations", &o.max_iterations, 1, 1000);
  c.readInRange("function_tolerance", &o.function_tolerance, 1e-12, 1e-1);
  c.readInRange("initial_trust_region_radius", &o.initial_trust_region_radius, 1e-3, 1e16);
  c.readInRange("max_trust_region_radius", &o.max_trust_region_radius, 1e-3, 1e16);
  c.readOptional("trust_region_warm_start", &o.trust_region_warm_start);
  if (o.max_trust_region_radius < o.initial_trust_region_radius)
    throw InputError(c.file(), 0,
                     "key '" + (c.path().empty() ? std::string("") : c.path() + ".") +
                         "max_trust_region_radius': must be >= initial_trust_region_radius");
  c.readEnum("linear_solver", &o.linear_solver,
             {{"dense_schur", ceres::DENSE_SCHUR},
              {"sparse_schur", ceres::SPARSE_SCHUR},
              {"sparse_normal_cholesky", ceres::SPARSE_NORMAL_CHOLESKY}});
  c.readOptional("landmarks_first", &o.landmarks_first);
  c.readEnum("optimizer", &o.optimizer,
             {{"ceres", OptimizerOptions::Optimizer::kCeres},
              {"schur_lm", OptimizerOptions::Optimizer::kSchurLm}});
  c.readInRange("max_solver_time_s", &o.max_solver_time_s, 1e-4, 1e4);
  c.readInRange("gyro_noise_density", &o.imu.gyro_noise_density, 1e-12, 1.0);
  c.readInRange("accel_noise_density", &o.imu.accel_noise_density, 1e-12, 10.0);
  c.readInRange("gyro_random_walk", &o.imu.gyro_random_walk, 1e-12, 1.0);
  c.readInRange("accel_random_walk", &o.imu.accel_random_walk, 1e-12, 10.0);
  readVec3(c, "thrust_noise_density", &o.thrust.thrust_noise_density, true);
  c.readInRange("thrust_direction_noise_density", &o.thrust.thrust_direction_noise_density, 1e-12, 1.0);
  readVec3(c, "residual_force_noise_density", &o.thrust.residual_force_noise_density, false);
  c.readInRange("force_random_walk", &o.dynamics.force_random_walk, 1e-6, 1e3);
  c.readInRange("force_prior_sigma", &o.dynamics.force_prior_sigma, 1e-6, 1e3);
  c.readOptional("force_walk_adaptive", &o.force_walk_adaptive.enabled);
  c.readInRange("force_walk_max", &o.force_walk_adaptive.max, 1e-6, 1e3);
  c.readInRange("force_walk_block_s", &o.force_walk_adaptive.block_s, 1e-3, 1e3);
  c.readInRange("force_walk_window_s", &o.force_walk_adaptive.window_s, 1e-3, 1e3);
  c.readInRange("force_walk_warmup_s", &o.force_walk_adaptive.warmup_s, 0.0, 1e3);
  if (o.force_walk_adaptive.enabled && o.force_walk_adaptive.window_s < o.force_walk_adaptive.block_s)
    throw InputError(c.file(), 0,
                     "key '" + (c.path().empty() ? std::string("") : c.path() + ".") +
                         "force_walk_window_s': must be >= force_walk_block_s");
  if (o.force_walk_adaptive.enabled && o.force_walk_adaptive.max < o.dynamics.force_random_walk)
    throw InputError(c.file(), 0,
                     "key '" + (c.path().empty() ? std::string("") : c.path() + ".") +
                         "force_walk_max': must be >= force_random_walk");
  readModelEnvelope(c, &o.model_envelope);
  c.readInRange("force_walk_outside_model", &o.force_walk_outside_model, 1e-6, 1e3);
  readVec3(c, "drag_linear", &o.dynamics.drag.linear, false);
  readVec3(c, "drag_quadratic", &o.dynamics.drag.quadratic, false);
  readVec3(c, "drag_rotor", &o.dynamics.drag.rotor, false);
  c.readInRange("drag_lift", &o.dynamics.drag.lift, 0.0, 10.0);
  readVec3(c, "drag_sigma", &o.dynamics.drag.sigma, false);
  readVec3(c, "drag_sigma_speed", &o.dynamics.drag.sigma_speed, false);
  readVec3(c, "drag_sigma_rate", &o.dynamics.drag.sigma_rate, false);
  readVec3(c, "drag_sigma_thrust", &o.dynamics.drag.sigma_thrust, false);
  if (o.dynamics.drag.enabled() && method == VioMethod::kVid)
    throw InputError(c.file(), 0,
                     "key '" + (c.path().empty() ? std::string("") : c.path() + ".") +
                         "drag_linear': vid's force prior is the accelerometer minus the thrust, "
                         "which already holds the drag; use it with vimo or hdvio");
  c.readInRange("init_velocity_sigma", &o.init_velocity_sigma, 1e-6, 100.0);
  c.readInRange("init_force_sigma", &o.init_force_sigma, 1e-6, 100.0);
  c.finish();
  finalize(&o);
  return o;
}

void adoptImuNoise(const ImuCalibration& calibration, const ConfigReader& section, VioBackendOptions* o) {
  const std::pair<const char*, std::pair<double, double*>> keys[] = {
      {"gyro_noise_density", {calibration.gyro_noise_density, &o->imu.gyro_noise_density}},
      {"accel_noise_density", {calibration.accel_noise_density, &o->imu.accel_noise_density}},
      {"gyro_random_walk", {calibration.gyro_random_walk, &o->imu.gyro_random_walk}},
      {"accel_random_walk", {calibration.accel_random_walk, &o->imu.accel_random_walk}}};
  for (const auto& [key, value] : keys) {
    if (section.has(key) || !(value.first > 0.0)) continue;
    *value.second = value.first;
    section.recordEffective(key, value.first);
  }
  finalize(o);
}

void adoptModelForceWalk(double walk, const ConfigReader& section, VioBackendOptions* o) {
  if (!(walk > o->dynamics.force_random_walk) || !std::isfinite(walk)) return;
  o->dynamics.force_random_walk = walk;
  section.recordEffective("force_random_walk", walk);
  if (o->force_walk_adaptive.max < walk) {
    o->force_walk_adaptive.max = walk;
    section.recordEffective("force_walk_max", walk);
  }
  finalize(o);
}

void adoptModelEnvelope(const ModelEnvelope& model, const ConfigReader& section, VioBackendOptions* o) {
  ModelEnvelope& e = o->model_envelope;
  if (!section.has("model_speed_max") && std::isfinite(model.speed_max)) {
    e.speed_max = model.speed_max;
    section.recordEffective("model_speed_max", model.speed_max);
  }
  if (!section.has("model_rate_max") && std::isfinite(model.rate_max)) {
    e.rate_max = model.rate_max;
    section.recordEffective("model_rate_max", model.rate_max);
  }
  if (!section.has("model_thrust_range") && std::isfinite(model.thrust_max)) {
    e.thrust_min = model.thrust_min;
    e.thrust_max = model.thrust_max;
    section.recordEffective("model_thrust_range", std::vector<double>{model.thrust_min, model.thrust_max});
  }
}

}  // namespace hdvio
