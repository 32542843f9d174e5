// Depth filters converge to the true depth on a simulated flight through the textured room.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "hdvio/frontend/depth_filter.h"
#include "hdvio/frontend/feature_detector.h"
#include "synthetic_room.h"

namespace hdvio::frontend {
namespace {

TEST(FrontendDepthFilter, SeedUpdateConvergesAndResistsOutliers) {
  Seed s;
  s.mu = 1.0 / 3.0;
  s.z_range = 2.0;
  s.sigma2 = s.z_range * s.z_range / 36.0;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> outlier(0.0, 2.0);
  const double truth = 1.0 / 4.5;
  for (int i = 0; i < 60; ++i) {
    const bool is_outlier = i % 5 == 4;  // 20 % gross outliers
    updateSeed(is_outlier ? outlier(rng) : truth + noise(rng), 0.01 * 0.01, &s);
  }
  EXPECT_NEAR(s.mu, truth, 0.005);
  EXPECT_LT(std::sqrt(s.sigma2), 0.003);
  EXPECT_GT(s.a / (s.a + s.b), 0.6);  // the inlier ratio is recognized as high
}

TEST(FrontendDepthFilter, SeedsConvergeOnSimulatedFlight) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const test::SyntheticRoom room;
  auto kf = std::make_shared<Frame>();
  const Pose T_w_kf = test::lookingForward(Vec3(-2.0, 0.5, 1.4), 0.15, 0.2);
  kf->T_cw = T_w_kf.inverse();
  kf->pyramid = buildPyramid(room.render(camera, T_w_kf), 5);
  kf->is_keyframe = true;
  const FeatureGrid grid(camera.width(), camera.height(), 32);
  std::vector<Feature> features;
  for (const Corner& c : detectCorners(kf->pyramid, DetectorOptions(), grid,
                                       std::vector<bool>(grid.cells(), false)))
    features.push_back({c.px, camera.unproject(c.px), c.level, -1});
  ASSERT_GT(features.size(), 100u);

  DepthFilter filter(camera, DepthFilterOptions());
  filter.addKeyframe(kf, features, 3.0, 0.5);  // true depths range from ~1.5 m to ~7 m
  std::vector<Seed> converged;
  // A sideways and forward flight of 25 frames at 20 Hz (~0.9 m/s) with a slight yaw.
  for (int k = 1; k <= 25; ++k) {
    Frame frame;
    frame.id = k;
    const Pose T_w_c = test::lookingForward(
        Vec3(-2.0 + 0.02 * k, 0.5 - 0.04 * k, 1.4 + 0.005 * k), 0.15 - 0.004 * k, 0.2);
    frame.T_cw = T_w_c.inverse();
    frame.pyramid = buildPyramid(room.render(camera, T_w_c), 5);
    for (Seed& s : filter.update(frame)) converged.push_back(s);
  }
  const double converged_ratio = static_cast<double>(converged.size()) / features.size();
  EXPECT_GT(converged_ratio, 0.6) << converged.size() << " of " << features.size();

  std::vector<double> rel_errors;
  for (const Seed& s : converged) {
    const double truth = room.depthAt(camera, T_w_kf, s.feature.px) / s.feature.f.z();  // range
    rel_errors.push_back(std::abs(s.depth() - truth) / truth);
  }
  ASSERT_FALSE(rel_errors.empty());
  std::sort(rel_errors.begin(), rel_errors.end());
  const double median = rel_errors[rel_errors.size() / 2];
  const double p90 = rel_errors[rel_errors.size() * 9 / 10];
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p90, 0.04);
  // Unconverged seeds still carry their uncertainty; none may have become invalid.
  for (const Seed& s : filter.seeds()) EXPECT_TRUE(std::isfinite(s.mu) && s.sigma2 > 0.0);
}

}  // namespace
}  // namespace hdvio::frontend
