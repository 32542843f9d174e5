#include <gtest/gtest.h>

#include "hdvio/frontend/gyro_prior.h"

namespace hdvio::frontend {
namespace {

TEST(FrontendGyroPrior, IntegratesHeldSamplesOverPartialIntervals) {
  std::vector<ImuSample> imu;
  for (int i = 0; i <= 20; ++i) {  // 200 Hz, constant rate until 50 ms, then a different one
    ImuSample s;
    s.t = i * 5'000'000LL;
    s.gyro = i < 10 ? Vec3(0.2, -0.1, 0.4) : Vec3(0.0, 0.0, -1.0);
    imu.push_back(s);
  }
  const Vec3 bias(0.01, 0.02, 0.03);
  // From 12.5 ms to 50 ms: 37.5 ms of the first rate only.
  const Quat q1 = integrateGyro(imu, 12'500'000, 50'000'000, bias);
  EXPECT_LT(quatLog(q1.conjugate() * quatExp((Vec3(0.2, -0.1, 0.4) - bias) * 0.0375)).norm(), 1e-12);
  // Across the change: 20 ms of each rate.
  const Quat q2 = integrateGyro(imu, 30'000'000, 70'000'000);
  const Quat expected = quatExp(Vec3(0.2, -0.1, 0.4) * 0.02) * quatExp(Vec3(0, 0, -1.0) * 0.02);
  EXPECT_LT(quatLog(q2.conjugate() * expected).norm(), 1e-12);
  EXPECT_LT(quatLog(integrateGyro(imu, 70'000'000, 30'000'000)).norm(), 1e-15);  // empty span
}

}  // namespace
}  // namespace hdvio::frontend
