#include "hdvio/learned/force_model_error.h"

#include <random>

#include <gtest/gtest.h>

namespace hdvio::learned {
namespace {

// Series of `seconds` at 100 Hz: white noise of `white` per sample on every axis plus, on the
// axes in `walk_axes`, a Wiener process of density `walk` (m/s^2/sqrt(s)).
std::vector<Vec3> errorSeries(double seconds, double white, double walk, const Vec3& walk_axes, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const double dt = 0.01;
  std::vector<Vec3> e;
  Vec3 slow = Vec3::Zero();
  for (int k = 0; k < static_cast<int>(seconds / dt); ++k) {
    slow += walk * std::sqrt(dt) * Vec3(n(rng), n(rng), n(rng)).cwiseProduct(walk_axes);
    e.push_back(slow + white * Vec3(n(rng), n(rng), n(rng)));
  }
  return e;
}

TEST(ForceModelError, WhiteErrorNeedsNoWalk) {
  // The accelerometer's noise alone (0.28 m/s^2 per sample): a model that is right needs none.
  const double w = modelErrorWalk({errorSeries(60, 0.28, 0.0, Vec3::Ones(), 1), errorSeries(60, 0.28, 0.0, Vec3::Ones(), 2)}, 100.0);
  EXPECT_LT(w, 0.04);
}

TEST(ForceModelError, SlowErrorGivesItsWalkDensity) {
  const std::vector<std::vector<Vec3>> s = {errorSeries(100, 0.05, 0.3, Vec3::Ones(), 3),
                                            errorSeries(100, 0.05, 0.3, Vec3::Ones(), 4)};
  EXPECT_NEAR(modelErrorWalk(s, 100.0), 0.3, 0.03);
  // Only along one axis: the isotropic walk is the mean of q over the axes.
  const std::vector<std::vector<Vec3>> z = {errorSeries(200, 0.05, 0.3, Vec3::UnitZ(), 5)};
  EXPECT_NEAR(modelErrorWalk(z, 100.0), 0.3 / std::sqrt(3.0), 0.02);
  // Under heavy white noise the walk is still found (the noise is subtracted, not counted).
  const std::vector<std::vector<Vec3>> noisy = {errorSeries(200, 0.5, 0.3, Vec3::Ones(), 6)};
  EXPECT_NEAR(modelErrorWalk(noisy, 100.0), 0.3, 0.04);
}

TEST(ForceModelError, TooShortSeriesGiveNone) {
  EXPECT_EQ(modelErrorWalk({errorSeries(0.7, 0.1, 1.0, Vec3::Ones(), 7)}, 100.0), 0.0);
  EXPECT_EQ(modelErrorWalk({}, 100.0), 0.0);
}

TEST(ForceModelError, ErrorIsMeasuredMinusThrustAndLaw) {
  FlightSamples f;
  f.name = "f";
  f.rate_hz = 100.0;
  DragLaw law;
  law.linear = Vec3(0.3, 0.3, 0.0);
  for (int k = 0; k < 5; ++k) {
    f.t.push_back(k * 10'000'000LL);
    f.thrust.push_back(Vec3(0, 0, 9.81));
    f.gyro.push_back(Vec3::Zero());
    f.p_W.push_back(Vec3::Zero());
    f.q_WB.push_back(Quat::Identity());
    f.v_W.push_back(Vec3(2.0, 0, 0));
    f.force.push_back(Vec3(-0.5, 0.1, 10.0));
  }
  const std::vector<Vec3> e = forceModelError(f, nullptr, law);
  ASSERT_EQ(e.size(), 5u);
  EXPECT_TRUE(e[0].isApprox(Vec3(-0.5 + 0.6, 0.1, 10.0 - 9.81), 1e-12));
  f.force.clear();
  EXPECT_THROW(forceModelError(f, nullptr, law), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
