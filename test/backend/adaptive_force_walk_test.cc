// The adaptive force walk against synthetic interval forces with the accelerometer's white
// noise: at the floor for a constant force, near the truth for a random-walk force, along the
// direction a force moves in when it moves in one only, at max while warming up.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "hdvio/backend/adaptive_force_walk.h"

namespace hdvio {
namespace {

constexpr double kDt = 0.05, kAccelNoise = 0.02, kFloor = 0.02;

// Walk chosen per interval over 120 s of interval-mean forces: a Wiener process with densities
// rw_true along the world axes U (sampled finely, averaged per interval) plus white noise of
// the accelerometer.
std::vector<ForceWalkAxes> runWalk(const Vec3& rw_true, const Mat3& U, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  AdaptiveForceWalk walk(AdaptiveForceWalkOptions{true, 5.0, 0.5, 4.0, 1.0}, kFloor, kAccelNoise);
  Vec3 f(1.0, -0.5, 0.2);
  const int substeps = 10;
  const double h = kDt / substeps;
  std::vector<ForceWalkAxes> out;
  for (int k = 0; k < static_cast<int>(120.0 / kDt); ++k) {
    Vec3 mean = Vec3::Zero();
    for (int s = 0; s < substeps; ++s) {
      f += U * (rw_true.cwiseProduct(std::sqrt(h) * Vec3(n(rng), n(rng), n(rng))));
      mean += f / substeps;
    }
    const Vec3 noise = (kAccelNoise / std::sqrt(kDt)) * Vec3(n(rng), n(rng), n(rng));
    out.push_back(walk.update(mean + noise, kDt));
  }
  return out;
}

std::vector<ForceWalkAxes> runWalk(double rw_true, unsigned seed) {
  return runWalk(Vec3::Constant(rw_true), Mat3::Identity(), seed);
}

// Each interval's walk as one number: the root mean square over the axes.
std::vector<double> rms(const std::vector<ForceWalkAxes>& walks) {
  std::vector<double> out;
  for (const ForceWalkAxes& w : walks) out.push_back(std::sqrt(w.density.squaredNorm() / 3.0));
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(AdaptiveForceWalk, StaysAtMaxUntilWarmedUp) {
  const std::vector<ForceWalkAxes> w = runWalk(0.0, 1);
  // Warmup 1 s = three 0.5-s blocks (two increments): the third block ends with interval 30.
  for (int k = 0; k < 29; ++k) EXPECT_EQ(w[k].density, Vec3::Constant(5.0)) << k;
  EXPECT_LT(w[29].density.maxCoeff(), 5.0);
}

TEST(AdaptiveForceWalk, ConstantForceGivesTheFloor) {
  for (unsigned seed : {2u, 3u}) {
    std::vector<ForceWalkAxes> walks = runWalk(0.0, seed);
    walks.erase(walks.begin(), walks.begin() + 100);  // after warmup and one full window
    std::vector<double> largest;
    for (const ForceWalkAxes& w : walks) {
      largest.push_back(w.density.maxCoeff());
      EXPECT_GE(w.density.minCoeff(), kFloor);
    }
    // The largest of three noisy eigenvalues is biased up; their mean is not.
    EXPECT_LT(median(rms(walks)), 0.05) << seed;
    EXPECT_LT(median(largest), 0.08) << seed;
    EXPECT_LT(*std::max_element(largest.begin(), largest.end()), 0.15) << seed;
  }
}

TEST(AdaptiveForceWalk, RandomWalkForceIsEstimated) {
  for (double rw : {0.2, 0.5}) {
    std::vector<double> w = rms(runWalk(rw, 4));
    w.erase(w.begin(), w.begin() + 100);
    const double m = median(w);
    std::printf("true walk %.2f: median estimate %.3f\n", rw, m);
    EXPECT_GT(m, 0.75 * rw);
    EXPECT_LT(m, 1.25 * rw);
  }
}

// A force that moves along one tilted direction only (a thrust model's error along a tilted
// body z axis): the walk is loose along it and at the floor across it. An isotropic estimate
// would spread the same evidence over three axes: sqrt(3) too tight along, too loose across.
TEST(AdaptiveForceWalk, ForceMovingAlongOneDirectionLoosensOnlyThatAxis) {
  const Vec3 along = Vec3(0.3, -0.2, 1.0).normalized();
  Mat3 U;
  U.col(2) = along;
  U.col(0) = along.cross(Vec3::UnitX()).normalized();
  U.col(1) = along.cross(U.col(0));
  for (unsigned seed : {5u, 6u}) {
    std::vector<ForceWalkAxes> walks = runWalk(Vec3(0.0, 0.0, 0.5), U, seed);
    walks.erase(walks.begin(), walks.begin() + 100);
    std::vector<double> dens_along, dens_across, alignment;
    for (const ForceWalkAxes& w : walks) {
      int k;
      dens_along.push_back(w.density.maxCoeff(&k));
      alignment.push_back(std::abs(w.axes_W.col(k).dot(along)));
      dens_across.push_back(std::max(w.density((k + 1) % 3), w.density((k + 2) % 3)));
    }
    std::printf("seed %u: along %.3f, across %.3f, |cos| %.3f (medians)\n", seed,
                median(dens_along), median(dens_across), median(alignment));
    EXPECT_GT(median(dens_along), 0.75 * 0.5) << seed;
    EXPECT_LT(median(dens_along), 1.25 * 0.5) << seed;
    EXPECT_LT(median(dens_across), 0.1) << seed;
    EXPECT_GT(median(alignment), 0.98) << seed;
  }
}

TEST(AdaptiveForceWalk, NoWarmupStillNeedsOneIncrement) {
  AdaptiveForceWalk walk(AdaptiveForceWalkOptions{true, 5.0, 0.5, 4.0, 0.0}, kFloor, kAccelNoise);
  for (int k = 0; k < 10; ++k)
    EXPECT_EQ(walk.update(Vec3(1.0, 0.0, 0.0), kDt).density, Vec3::Constant(5.0)) << k;
  for (int k = 0; k < 10; ++k) {
    const ForceWalkAxes w = walk.update(Vec3(1.0, 0.0, 0.0), kDt);
    EXPECT_TRUE(w.density.allFinite() && w.axes_W.allFinite());
    if (k == 9) {
      EXPECT_EQ(w.density, Vec3::Constant(kFloor));  // the second block: one increment, no change
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
