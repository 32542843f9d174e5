// Checks that each dataset's mapping to the Sequence conventions is physically consistent:
// the IMU's gravity-compensated specific force, rotated to the world, must integrate to the
// ground-truth velocity change, and the gyro must match the ground-truth attitude change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hdvio/io/datasets.h"
#include "hdvio/io/sequence_reader.h"
#include "test_data.h"

namespace hdvio::io {
namespace {

struct Agreement {
  double accel_rms_error = 0.0, accel_rms_signal = 0.0;
  double gyro_rms_error = 0.0, gyro_rms_signal = 0.0;
  int windows = 0;
};

// Over windows of `window` ground-truth samples: mean(R a + g) vs (v_end - v_start) / dt, and
// mean(gyro) vs Log(R_start^T R_end) / dt. IMU and ground truth share timestamps row by row in
// all three HDF5/CSV datasets, so samples are indexed together.
Agreement compare(const Sequence& seq, std::size_t window) {
  Agreement a;
  const auto& gt = seq.groundtruth;
  EXPECT_EQ(gt.size(), seq.imu.size());
  double ea = 0, sa = 0, eg = 0, sg = 0;
  for (std::size_t k = 0; k + window < gt.size(); k += window) {
    const double dt = secondsBetween(gt[k].t, gt[k + window].t);
    Vec3 mean_acc = Vec3::Zero(), mean_gyro = Vec3::Zero();
    for (std::size_t i = k; i < k + window; ++i) {
      // Trapezoid over [t_i, t_i+1], weighted by the true spacing (DIDO's clock jitters).
      const double h = secondsBetween(gt[i].t, gt[i + 1].t);
      const Vec3 a0 = gt[i].T_WB.q * seq.imu[i].accel, a1 = gt[i + 1].T_WB.q * seq.imu[i + 1].accel;
      mean_acc += 0.5 * h * (a0 + a1);
      mean_gyro += 0.5 * h * (seq.imu[i].gyro + seq.imu[i + 1].gyro);
    }
    mean_acc = mean_acc / dt + gravityWorld();
    mean_gyro /= dt;
    const Vec3 dv = (gt[k + window].v_W - gt[k].v_W) / dt;
    const Vec3 dtheta = quatLog(gt[k].T_WB.q.conjugate() * gt[k + window].T_WB.q) / dt;
    ea += (mean_acc - dv).squaredNorm();
    sa += dv.squaredNorm();
    eg += (mean_gyro - dtheta).squaredNorm();
    sg += dtheta.squaredNorm();
    ++a.windows;
  }
  a.accel_rms_error = std::sqrt(ea / a.windows);
  a.accel_rms_signal = std::sqrt(sa / a.windows);
  a.gyro_rms_error = std::sqrt(eg / a.windows);
  a.gyro_rms_signal = std::sqrt(sg / a.windows);
  std::printf("  %s: %d windows, accel rms error %.3f vs signal %.3f m/s^2, gyro rms error %.4f vs signal %.4f rad/s\n",
              seq.name.c_str(), a.windows, a.accel_rms_error, a.accel_rms_signal, a.gyro_rms_error,
              a.gyro_rms_signal);
  return a;
}

TEST(DatasetFrames, BlackbirdImuMatchesGroundTruth) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdTrain);
  const Sequence seq = readBlackbird(test::dataPath(test::kBlackbirdTrain));
  const Agreement a = compare(seq, 10);  // 0.1 s windows at 100 Hz
  EXPECT_LT(a.accel_rms_error, 0.35 * a.accel_rms_signal);
  EXPECT_LT(a.gyro_rms_error, 0.1 * a.gyro_rms_signal);
}

TEST(DatasetFrames, BlackbirdThrustAlongSpecificForce) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdTrain);
  const Sequence seq = readBlackbird(test::dataPath(test::kBlackbirdTrain));
  ASSERT_EQ(seq.thrust.size(), seq.imu.size());
  double mean_cos = 0.0, mean_ratio = 0.0;
  for (std::size_t i = 0; i < seq.imu.size(); ++i) {
    const Vec3& T = seq.thrust[i].thrust;
    const Vec3& a = seq.imu[i].accel;
    mean_cos += T.dot(a) / (T.norm() * a.norm());
    mean_ratio += T.norm() / a.norm();
  }
  mean_cos /= seq.imu.size();
  mean_ratio /= seq.imu.size();
  std::printf("  blackbird thrust vs accel: mean cos %.4f, mean |T|/|a| %.4f\n", mean_cos, mean_ratio);
  EXPECT_GT(mean_cos, 0.98);  // both point along the IMU -z axis (z down when hovering)
  EXPECT_NEAR(mean_ratio, 1.0, 0.15);
  EXPECT_LT(seq.thrust.front().thrust.z(), -8.0);  // hover thrust ~ (0, 0, -g)
}

TEST(DatasetFrames, DidoImuMatchesGroundTruth) {
  for (const char* rel : {test::kDido4Col, test::kDido5Col}) {
    HDVIO_REQUIRE_DATA(rel);
    const Sequence seq = readDido(test::dataPath(rel));
    const Agreement a = compare(seq, 40);  // ~0.1 s windows at 400 Hz
    EXPECT_LT(a.accel_rms_error, 0.35 * a.accel_rms_signal) << rel;
    EXPECT_LT(a.gyro_rms_error, 0.1 * a.gyro_rms_signal) << rel;
  }
}

TEST(DatasetFrames, NeuroBemImuMatchesGroundTruth) {
  HDVIO_REQUIRE_DATA(test::kNeuroBem);
  const Sequence seq = readNeuroBem(test::dataPath(test::kNeuroBem));
  const Agreement a = compare(seq, 40);
  EXPECT_LT(a.accel_rms_error, 0.35 * a.accel_rms_signal);
  EXPECT_LT(a.gyro_rms_error, 0.1 * a.gyro_rms_signal);
}

}  // namespace
}  // namespace hdvio::io
