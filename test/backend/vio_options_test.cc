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

}  // namespace
}  // namespace hdvio
