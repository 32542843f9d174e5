// The backend's options: the IMU noise of the sequence's calibration where the experiment is silent.
#include <gtest/gtest.h>

#include "hdvio/backend/vio_options.h"

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

}  // namespace
}  // namespace hdvio
