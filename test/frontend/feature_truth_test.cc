// hdvio_feature_truth's checker (apps/frontend_demo/feature_truth.h): rays meet the room where
// they should, and an observation placed at a known offset from the true projection of its
// landmark's first ray is reported with exactly that error, with the camera mounted off the
// body frame (T_BS) as on the simulator's flights.
#include "feature_truth.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hdvio/sim/scene.h"

namespace hdvio {
namespace {

sim::Scene room() {
  sim::SceneConfig c;
  c.room_min = Vec3(-4.0, -3.0, 0.0);
  c.room_max = Vec3(4.0, 3.0, 3.0);
  c.texel_size = 0.1;
  return sim::Scene(c, {}, 1);
}

TEST(FeatureTruth, RayMeetsTheNearestWall) {
  const sim::Scene scene = room();
  EXPECT_NEAR(castRay(scene, Vec3(0, 0, 1.5), Vec3(1, 0, 0)), 4.0, 1e-12);
  EXPECT_NEAR(castRay(scene, Vec3(1, 0, 1.5), Vec3(0, 0, -1)), 1.5, 1e-12);
  const Vec3 d = Vec3(1, 1, 0).normalized();  // the y wall (3 m) comes before the x wall (4 m)
  EXPECT_NEAR(castRay(scene, Vec3(0, 0, 1.5), d), 3.0 * std::sqrt(2.0), 1e-12);
  EXPECT_LT(castRay(scene, Vec3(5, 0, 1.5), Vec3(1, 0, 0)), 0.0);  // outside the room
}

TEST(FeatureTruth, ReportsTheOffsetFromTheTrueProjection) {
  const sim::Scene scene = room();
  const CameraModel camera(320, 240, 200.0, 200.0, 160.0, 120.0, DistortionModel::kRadialTangential,
                           {-0.05, 0.01, 0.0002, -0.0001});
  // Forward-looking camera (optical axis = body x), as the simulator mounts it.
  Mat3 R_BS;
  R_BS << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Pose T_BS(R_BS, Vec3(0.05, 0.0, 0.02));
  const auto truth = [](Timestamp t) {
    const double s = toSeconds(t);
    return Pose(Quat(Eigen::AngleAxisd(0.2 * s, Vec3::UnitZ())), Vec3(0.5 * s, 0.3 * s, 1.5));
  };
  FeatureTruthChecker checker(scene, camera, T_BS, truth);

  const Vec2 px0(100.0, 80.0);
  ImageStep first;
  first.record.t = 0;
  first.record.tracked = true;
  first.observations.push_back({7, px0, Vec3::UnitZ(), 0});
  checker.add(first);

  // The true point of landmark 7, seen from the second pose, moved by (0.6, -0.8) px.
  const Timestamp t1 = fromSeconds(0.5);
  const Pose T_WC0 = truth(0) * T_BS;
  const Vec3 d = T_WC0.q * camera.unproject(px0).normalized();
  const Vec3 p_W = T_WC0.p + castRay(scene, T_WC0.p, d) * d;
  Vec2 uv;
  ASSERT_TRUE(camera.project((truth(t1) * T_BS).inverse() * p_W, &uv));
  ImageStep second;
  second.record.t = t1;
  second.record.tracked = true;
  second.observations.push_back({7, uv + Vec2(0.6, -0.8), Vec3::UnitZ(), 1});
  checker.add(second);

  const FeatureTruthSummary s = checker.summary();
  ASSERT_EQ(s.all.count, 1);  // the first observation defines the point
  EXPECT_NEAR(s.all.median, 1.0, 1e-6);
  EXPECT_NEAR(s.all.rms, 1.0, 1e-6);
  ASSERT_EQ(s.by_level.count(1), 1u);
  EXPECT_EQ(s.landmarks, 1);
  EXPECT_DOUBLE_EQ(s.track_mean, 2.0);
}

}  // namespace
}  // namespace hdvio
