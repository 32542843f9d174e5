#pragma once
// Sample-by-sample equality of two sequences (exact for values written with full precision).
#include <gtest/gtest.h>

#include "hdvio/core/sequence.h"

namespace hdvio::io::test {

inline void expectSameSamples(const Sequence& a, const Sequence& b) {
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t i = 0; i < a.imu.size(); ++i) {
    ASSERT_EQ(a.imu[i].t, b.imu[i].t) << i;
    ASSERT_EQ(a.imu[i].gyro, b.imu[i].gyro) << i;
    ASSERT_EQ(a.imu[i].accel, b.imu[i].accel) << i;
  }
  ASSERT_EQ(a.thrust.size(), b.thrust.size());
  for (std::size_t i = 0; i < a.thrust.size(); ++i) {
    ASSERT_EQ(a.thrust[i].t, b.thrust[i].t) << i;
    ASSERT_EQ(a.thrust[i].thrust, b.thrust[i].thrust) << i;
  }
  ASSERT_EQ(a.rotor.size(), b.rotor.size());
  for (std::size_t i = 0; i < a.rotor.size(); ++i) {
    ASSERT_EQ(a.rotor[i].t, b.rotor[i].t) << i;
    ASSERT_EQ(a.rotor[i].speeds, b.rotor[i].speeds) << i;
  }
  ASSERT_EQ(a.groundtruth.size(), b.groundtruth.size());
  for (std::size_t i = 0; i < a.groundtruth.size(); ++i) {
    const GroundTruthState &x = a.groundtruth[i], &y = b.groundtruth[i];
    ASSERT_EQ(x.t, y.t) << i;
    ASSERT_EQ(x.T_WB.p, y.T_WB.p) << i;
    ASSERT_EQ(x.T_WB.q.coeffs(), y.T_WB.q.coeffs()) << i;
    ASSERT_EQ(x.has_velocity, y.has_velocity) << i;
    ASSERT_EQ(x.has_biases, y.has_biases) << i;
    ASSERT_EQ(x.v_W, y.v_W) << i;
    ASSERT_EQ(x.gyro_bias, y.gyro_bias) << i;
    ASSERT_EQ(x.accel_bias, y.accel_bias) << i;
  }
  ASSERT_EQ(a.forces.size(), b.forces.size());
  for (std::size_t i = 0; i < a.forces.size(); ++i) {
    ASSERT_EQ(a.forces[i].t, b.forces[i].t) << i;
    ASSERT_EQ(a.forces[i].external, b.forces[i].external) << i;
    ASSERT_EQ(a.forces[i].drag, b.forces[i].drag) << i;
  }
  ASSERT_EQ(a.landmarks, b.landmarks);
  ASSERT_EQ(a.landmark_observations.size(), b.landmark_observations.size());
  for (std::size_t i = 0; i < a.landmark_observations.size(); ++i) {
    const auto &x = a.landmark_observations[i], &y = b.landmark_observations[i];
    ASSERT_EQ(x.t, y.t);
    ASSERT_EQ(x.landmark_id, y.landmark_id);
    ASSERT_EQ(x.u, y.u);
    ASSERT_EQ(x.v, y.v);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) ASSERT_EQ(a.images[i].t, b.images[i].t);
  ASSERT_EQ(a.rotor_calibration.has_value(), b.rotor_calibration.has_value());
  if (a.rotor_calibration) {
    EXPECT_EQ(a.rotor_calibration->mass, b.rotor_calibration->mass);
    EXPECT_EQ(a.rotor_calibration->thrust_coefficient, b.rotor_calibration->thrust_coefficient);
    EXPECT_EQ(a.rotor_calibration->thrust_axis, b.rotor_calibration->thrust_axis);
  }
  ASSERT_EQ(a.camera.has_value(), b.camera.has_value());
  if (a.camera) {
    const CameraCalibration &x = *a.camera, &y = *b.camera;
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(x.rate_hz, y.rate_hz);
    EXPECT_EQ(x.fu, y.fu);
    EXPECT_EQ(x.fv, y.fv);
    EXPECT_EQ(x.cu, y.cu);
    EXPECT_EQ(x.cv, y.cv);
    EXPECT_EQ(x.distortion, y.distortion);
    EXPECT_EQ(x.distortion_coefficients, y.distortion_coefficients);
    // T_BS goes through a 4x4 matrix and back: equal up to rounding.
    EXPECT_TRUE(x.T_BS.matrix().isApprox(y.T_BS.matrix(), 1e-14));
  }
  ASSERT_EQ(a.imu_calibration.has_value(), b.imu_calibration.has_value());
  if (a.imu_calibration) {
    EXPECT_EQ(a.imu_calibration->rate_hz, b.imu_calibration->rate_hz);
    EXPECT_EQ(a.imu_calibration->gyro_noise_density, b.imu_calibration->gyro_noise_density);
    EXPECT_EQ(a.imu_calibration->gyro_random_walk, b.imu_calibration->gyro_random_walk);
    EXPECT_EQ(a.imu_calibration->accel_noise_density, b.imu_calibration->accel_noise_density);
    EXPECT_EQ(a.imu_calibration->accel_random_walk, b.imu_calibration->accel_random_walk);
    EXPECT_TRUE(a.imu_calibration->T_BS.matrix().isApprox(b.imu_calibration->T_BS.matrix(), 1e-14));
  }
}

}  // namespace hdvio::io::test
