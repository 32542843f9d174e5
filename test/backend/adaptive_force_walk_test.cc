// The adaptive force walk against synthetic interval forces with the accelerometer's white
// noise: at the floor for a constant force, near the truth for a random-walk force, at max
// while warming up.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "hdvio/backend/adaptive_force_walk.h"

namespace hdvio {
namespace {

constexpr double kDt = 0.05, kAccelNoise = 0.02, kFloor = 0.02;

// Walk chosen per interval over 120 s of interval-mean forces: a Wiener process of density
// q_true (sampled finely, averaged per interval) plus white noise of the accelerometer.
std::vector<double> runWalk(double rw_true, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  AdaptiveForceWalk walk(AdaptiveForceWalkOptions{true, 5.0, 0.5, 4.0, 1.0}, kFloor, kAccelNoise);
  Vec3 f(1.0, -0.5, 0.2);
  const int substeps = 10;
  const double h = kDt / substeps;
  std::vector<double> out;
  for (int k = 0; k < static_cast<int>(120.0 / kDt); ++k) {
    Vec3 mean = Vec3::Zero();
    for (int s = 0; s < substeps; ++s) {
      f += rw_true * std::sqrt(h) * Vec3(n(rng), n(rng), n(rng));
      mean += f / substeps;
    }
    const Vec3 noise = (kAccelNoise / std::sqrt(kDt)) * Vec3(n(rng), n(rng), n(rng));
    out.push_back(walk.update(mean + noise, kDt));
  }
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(AdaptiveForceWalk, StaysAtMaxUntilWarmedUp) {
  const std::vector<double> w = runWalk(0.0, 1);
  // Warmup 1 s = three 0.5-s blocks (two increments): the third block ends with interval 30.
  for (int k = 0; k < 29; ++k) EXPECT_EQ(w[k], 5.0) << k;
  EXPECT_LT(w[29], 5.0);
}

TEST(AdaptiveForceWalk, ConstantForceGivesTheFloor) {
  for (unsigned seed : {2u, 3u}) {
    std::vector<double> w = runWalk(0.0, seed);
    w.erase(w.begin(), w.begin() + 100);  // after warmup and one full window
    EXPECT_LT(median(w), 0.04) << seed;
    EXPECT_LT(*std::max_element(w.begin(), w.end()), 0.12) << seed;
    EXPECT_GE(*std::min_element(w.begin(), w.end()), kFloor);
  }
}

TEST(AdaptiveForceWalk, RandomWalkForceIsEstimated) {
  for (double rw : {0.2, 0.5}) {
    std::vector<double> w = runWalk(rw, 4);
    w.erase(w.begin(), w.begin() + 100);
    const double m = median(w);
    std::printf("true walk %.2f: median estimate %.3f\n", rw, m);
    EXPECT_GT(m, 0.75 * rw);
    EXPECT_LT(m, 1.25 * rw);
  }
}

TEST(AdaptiveForceWalk, NoWarmupStillNeedsOneIncrement) {
  AdaptiveForceWalk walk(AdaptiveForceWalkOptions{true, 5.0, 0.5, 4.0, 0.0}, kFloor, kAccelNoise);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(walk.update(Vec3(1.0, 0.0, 0.0), kDt), 5.0) << k;
  for (int k = 0; k < 10; ++k) {
    const double w = walk.update(Vec3(1.0, 0.0, 0.0), kDt);
    EXPECT_TRUE(std::isfinite(w));
    if (k == 9) {
      EXPECT_EQ(w, kFloor);  // the second block: one increment, no change
    }
  }
}

TEST(AdaptiveForceWalk, RejectsInconsistentOptions) {
  EXPECT_THROW(AdaptiveForceWalk(AdaptiveForceWalkOptions{true, 0.01, 0.5, 4.0, 1.0}, 0.02, 0.02),
               std::invalid_argument);
  EXPECT_THROW(AdaptiveForceWalk(AdaptiveForceWalkOptions{true, 5.0, 0.5, 0.2, 0.1}, 0.02, 0.02),
               std::invalid_argument);
}

}  // namespace
}  // namespace hdvio
