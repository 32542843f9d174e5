// The backend's options: the IMU noise of the sequence's calibration where the experiment is silent.
#include <cmath>

#include <gtest/gtest.h>

#include "hdvio/backend/vio_options.h"
#include "hdvio/core/error.h"

namespace hdvio {
namespace {

ImuCalibration calibration() {
  ImuCalibration c;
  c.gyro_noise_density = 3e-4;
  c.accel_noise_density = 4e-3;
  c.gyro_random_walk = 5e-5;
  c.accel_random_walk = 0.0;  // not given: the default stays
  return c;
}

TEST(VioOptions, ImuNoiseComesFromTheCalibrationUnlessTheExperimentGivesIt) {
  const ConfigReader cfg = ConfigReader::fromString("backend: {accel_noise_density: 0.02}\n");
  const ConfigReader backend = cfg.section("backend");
  VioBackendOptions o = loadVioBackendOptions(backend, VioMethod::kVimo);
  const double default_accel_walk = o.imu.accel_random_walk;
  adoptImuNoise(calibration(), backend, &o);
  EXPECT_EQ(o.imu.gyro_noise_density, 3e-4);
  EXPECT_EQ(o.imu.accel_noise_density, 0.02);  // the experiment's
  EXPECT_EQ(o.imu.gyro_random_walk, 5e-5);
  EXPECT_EQ(o.imu.accel_random_walk, default_accel_walk);
  // The thrust model's gyro terms follow the IMU's.
  EXPECT_EQ(o.thrust.gyro_noise_density, 3e-4);
  EXPECT_EQ(o.thrust.gyro_random_walk, 5e-5);
  // The effective configuration says what ran.
  const YAML::Node eff = YAML::Load(cfg.effectiveYaml())["backend"];
  EXPECT_EQ(eff["gyro_noise_density"].as<double>(), 3e-4);
  EXPECT_EQ(eff["accel_noise_density"].as<double>(), 0.02);
  EXPECT_EQ(eff["gyro_random_walk"].as<double>(), 5e-5);
  EXPECT_EQ(eff["accel_random_walk"].as<double>(), default_accel_walk);
}

// The window's solver is chosen once, by name; a name it does not know is an input error.
TEST(VioOptions, TheOptimizerIsChosenByName) {
  EXPECT_EQ(loadVioBackendOptions(ConfigReader::fromString("backend: {}\n").section("backend"), VioMethod::kVio)
                .optimizer,
            OptimizerOptions::Optimizer::kCeres);
  EXPECT_EQ(loadVioBackendOptions(ConfigReader::fromString("backend: {optimizer: schur_lm}\n").section("backend"),
                                  VioMethod::kVio)
                .optimizer,
            OptimizerOptions::Optimizer::kSchurLm);
  EXPECT_THROW(loadVioBackendOptions(ConfigReader::fromString("backend: {optimizer: gtsam}\n").section("backend"),
                                     VioMethod::kVio),
               InputError);
}

// The residual-force model's error walk is the least walk of the external force: it raises a
// lower floor (and the adaptive walk's ceiling if need be), never lowers a higher one.
TEST(VioOptions, TheModelsErrorWalkIsTheLeastForceWalk) {
  const ConfigReader cfg = ConfigReader::fromString("backend: {force_random_walk: 0.02, force_walk_max: 0.1}\n");
  const ConfigReader backend = cfg.section("backend");
  VioBackendOptions o = loadVioBackendOptions(backend, VioMethod::kHdvio);
  adoptModelForceWalk(0.0, backend, &o);  // a file that does not say
  EXPECT_EQ(o.dynamics.force_random_walk, 0.02);
  adoptModelForceWalk(0.21, backend, &o);
  EXPECT_EQ(o.dynamics.force_random_walk, 0.21);
  EXPECT_EQ(o.force_walk_adaptive.max, 0.21);
  const YAML::Node eff = YAML::Load(cfg.effectiveYaml())["backend"];
  EXPECT_EQ(eff["force_random_walk"].as<double>(), 0.21);
  EXPECT_EQ(eff["force_walk_max"].as<double>(), 0.21);
  adoptModelForceWalk(0.1, backend, &o);  // below the floor: no change
  EXPECT_EQ(o.dynamics.force_random_walk, 0.21);
}

// The model's training envelope bounds what the experiment does not bound itself.
TEST(VioOptions, TheModelsEnvelopeFillsTheBoundsTheExperimentLeaves) {
  const ConfigReader cfg = ConfigReader::fromString("backend: {model_rate_max: 2.5}\n");
  const ConfigReader backend = cfg.section("backend");
  VioBackendOptions o = loadVioBackendOptions(backend, VioMethod::kHdvio);
  EXPECT_TRUE(std::isinf(o.model_envelope.speed_max));
  EXPECT_EQ(o.model_envelope.rate_max, 2.5);
  ModelEnvelope model;
  model.speed_max = 9.0;
  model.rate_max = 1.3;
  model.thrust_min = 8.9;
  model.thrust_max = 13.4;
  adoptModelEnvelope(model, backend, &o);
  EXPECT_EQ(o.model_envelope.speed_max, 9.0);
  EXPECT_EQ(o.model_envelope.rate_max, 2.5);  // the experiment's
  EXPECT_EQ(o.model_envelope.thrust_min, 8.9);
  EXPECT_EQ(o.model_envelope.thrust_max, 13.4);
  const YAML::Node eff = YAML::Load(cfg.effectiveYaml())["backend"];
  EXPECT_EQ(eff["model_speed_max"].as<double>(), 9.0);
  EXPECT_EQ(eff["model_rate_max"].as<double>(), 2.5);
  EXPECT_EQ(eff["model_thrust_range"][0].as<double>(), 8.9);
  const ConfigReader bad = ConfigReader::fromString("backend: {model_thrust_range: [12, 9]}\n", "b.yaml");
  try {
    loadVioBackendOptions(bad.section("backend"), VioMethod::kHdvio);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model_thrust_range': needs 0 <= min < max"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hdvio
