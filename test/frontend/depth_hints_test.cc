// A new map's corners take their initial depths from known 3-D points (depth_hints.h).
#include "hdvio/frontend/depth_hints.h"

#include <gtest/gtest.h>

#include "synthetic_room.h"

namespace hdvio::frontend {
namespace {

TEST(FrontendDepthHints, NearestPointInRadiusElseMedianElseFallback) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const Pose T_wc = test::lookingForward(Vec3(1.0, -0.5, 1.2), 0.3, 0.1);
  const Pose T_cw = T_wc.inverse();
  // Points at known ranges along the rays of three pixels, and one behind the camera.
  const auto at = [&](const Vec2& px, double range) { return T_wc * (camera.unproject(px) * range); };
  const std::vector<Vec3> points{at({100, 100}, 2.0), at({300, 200}, 8.0), at({200, 60}, 5.0),
                                 T_wc * Vec3(0.0, 0.0, -4.0)};
  const std::vector<Vec2> corners{{104, 97}, {296, 205}, {40, 220}, {200, 64}};
  const std::vector<double> d = hintedDepths(camera, T_cw, corners, points, 32.0, 3.0, 0.5);
  ASSERT_EQ(d.size(), corners.size());
  EXPECT_NEAR(d[0], 2.0, 1e-9);  // nearest point within 32 px
  EXPECT_NEAR(d[1], 8.0, 1e-9);
  EXPECT_NEAR(d[2], 5.0, 1e-9);  // none within 32 px: median of the 3 points in view
  EXPECT_NEAR(d[3], 5.0, 1e-9);

  // No points: the fallback; the minimum depth bounds every hint.
  for (double x : hintedDepths(camera, T_cw, corners, {}, 32.0, 3.0, 0.5)) EXPECT_EQ(x, 3.0);
  const std::vector<double> clamped = hintedDepths(camera, T_cw, corners, points, 32.0, 3.0, 2.5);
  EXPECT_EQ(clamped[0], 2.5);
  EXPECT_NEAR(clamped[1], 8.0, 1e-9);
}

}  // namespace
}  // namespace hdvio::frontend
