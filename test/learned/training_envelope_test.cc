#include "hdvio/learned/training_envelope.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hdvio::learned {
namespace {

// A flight whose speed, rate and thrust run linearly over [0, 1) times their scale, with one
// sample of each far outside (a glitch).
FlightSamples rampFlight(int n, double speed, double rate, double thrust_lo, double thrust_hi) {
  FlightSamples f;
  f.rate_hz = 100.0;
  for (int k = 0; k < n; ++k) {
    const double s = static_cast<double>(k) / n;
    f.t.push_back(k * 10'000'000LL);
    f.v_W.push_back(Vec3(0.6, 0.0, 0.8) * speed * s);
    f.gyro.push_back(Vec3(0.0, 0.0, -1.0) * rate * s);
    f.thrust.push_back(Vec3::UnitZ() * (thrust_lo + (thrust_hi - thrust_lo) * s));
    f.p_W.push_back(Vec3::Zero());
    f.q_WB.push_back(Quat::Identity());
  }
  f.v_W[n / 2] *= 100.0;
  f.gyro[n / 3] = Vec3(250.0, 0.0, 0.0);
  f.thrust[n / 4] = Vec3::UnitZ() * 60.0;
  return f;
}

TEST(TrainingEnvelope, HoldsAllButTheRarestSamples) {
  const ModelEnvelope e = trainingEnvelope({rampFlight(1000, 4.0, 2.0, 8.0, 12.0), rampFlight(1000, 2.0, 1.0, 9.0, 10.0)});
  // The 99th percentile of the pooled samples: near the faster flight's top, not the glitches.
  EXPECT_NEAR(e.speed_max, 3.92, 0.02);
  EXPECT_NEAR(e.rate_max, 1.96, 0.01);
  EXPECT_NEAR(e.thrust_min, 8.08, 0.02);
  EXPECT_NEAR(e.thrust_max, 11.92, 0.02);
  EXPECT_TRUE(e.contains(3.0, 1.5, 10.0));
  EXPECT_FALSE(e.contains(4.5, 1.5, 10.0));
  EXPECT_FALSE(e.contains(3.0, 2.5, 10.0));
  EXPECT_FALSE(e.contains(3.0, 1.5, 7.0));
  EXPECT_FALSE(e.contains(3.0, 1.5, 13.0));
  // How far outside, relative to the bound it crosses.
  EXPECT_EQ(e.excess(3.0, 1.5, 10.0), 0.0);
  EXPECT_NEAR(e.excess(1.5 * e.speed_max, 1.5, 10.0), 0.5, 1e-12);
  EXPECT_NEAR(e.excess(3.0, 1.5, 0.5 * e.thrust_min), 1.0, 1e-12);
  EXPECT_NEAR(e.excess(2.0 * e.speed_max, 3.0 * e.rate_max, 10.0), 2.0, 1e-12);
  EXPECT_FALSE(e.unbounded());
  EXPECT_TRUE(ModelEnvelope().unbounded());
  EXPECT_THROW(trainingEnvelope({}), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
