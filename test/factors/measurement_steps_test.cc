// Splitting IMU / thrust streams into integration steps over [t_i, t_j].
#include <gtest/gtest.h>

#include "hdvio/core/error.h"
#include "hdvio/factors/measurement_steps.h"

namespace hdvio {
namespace {

// Linear signals: the trapezoid average of a step equals the signal at the step's midpoint.
TEST(MeasurementSteps, UnionOfRatesAndLinearInterpolation) {
  std::vector<ImuSample> imu;
  for (int k = 0; k <= 100; ++k) {
    const double t = k * 0.01;
    imu.push_back({fromSeconds(t), Vec3(t, 2 * t, -t), Vec3(1, 2, 3 + t)});
  }
  std::vector<ThrustSample> thrust;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.007 + k * 0.025;
    thrust.push_back({fromSeconds(t), Vec3(0, 0, 9 + t)});
  }
  const Timestamp ti = fromSeconds(0.2035), tj = fromSeconds(0.5012);
  const auto steps = dynamicsSteps(imu, thrust, ti, tj);
  double total = 0.0, t = toSeconds(ti);
  for (const auto& s : steps) {
    ASSERT_GT(s.dt, 0.0);
    const double mid = t + 0.5 * s.dt;
    EXPECT_NEAR(s.gyro.y(), 2 * mid, 1e-9);
    EXPECT_NEAR(s.accel.z(), 3 + mid, 1e-9);
    EXPECT_NEAR(s.thrust.z(), 9 + mid, 1e-9);
    total += s.dt;
    t += s.dt;
  }
  EXPECT_NEAR(total, toSeconds(tj) - toSeconds(ti), 1e-12);
  // 30 IMU times (0.21 .. 0.50) and 12 thrust times inside the interval -> 43 steps.
  EXPECT_EQ(steps.size(), 43u);
  EXPECT_EQ(imuSteps(imu, ti, tj).size(), 31u);
}

TEST(MeasurementSteps, RejectsBadStreams) {
  std::vector<ImuSample> imu;
  for (int k = 0; k <= 10; ++k) imu.push_back({fromSeconds(k * 0.01), Vec3::Zero(), Vec3::Zero()});
  EXPECT_THROW(imuSteps(imu, fromSeconds(0.05), fromSeconds(0.2)), InputError);  // not covered
  EXPECT_THROW(imuSteps(imu, fromSeconds(0.05), fromSeconds(0.05)), InputError);  // empty
  auto unordered = imu;
  std::swap(unordered[4].t, unordered[5].t);
  EXPECT_THROW(imuSteps(unordered, fromSeconds(0.0), fromSeconds(0.08)), InputError);
  EXPECT_NO_THROW(imuSteps(imu, fromSeconds(0.0), fromSeconds(0.1)));
}

}  // namespace
}  // namespace hdvio
