// hdvio_feature_truth's checker without a scene (apps/frontend_demo/track_geometry.h): exact
// projections of a point score zero; one observation moved off its projection raises the error;
// a track too short or without parallax is not scored.
#include "track_geometry.h"

#include <gtest/gtest.h>

namespace hdvio {
namespace {

class TrackGeometry : public ::testing::Test {
 protected:
  TrackGeometry()
      : camera_(320, 240, 200.0, 200.0, 160.0, 120.0, DistortionModel::kRadialTangential,
                {-0.05, 0.01, 0.0002, -0.0001}) {
    Mat3 R_BS;  // forward-looking camera (optical axis = body x)
    R_BS << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    T_BS_ = Pose(R_BS, Vec3(0.05, 0.0, 0.02));
  }
  static Pose truth(Timestamp t) {
    const double s = toSeconds(t);
    return Pose(Quat(Eigen::AngleAxisd(0.1 * s, Vec3::UnitZ())), Vec3(0.2 * s, 1.0 * s, 1.5));
  }
  // Image k at 0.1 k s with landmark `id` at p_W, its projection moved by `offset`.
  ImageStep image(int k, const std::vector<std::pair<int, Vec3>>& points, const Vec2& offset = Vec2::Zero()) {
    ImageStep step;
    step.record.t = fromSeconds(0.1 * k);
    step.record.tracked = true;
    for (const auto& [id, p_W] : points) {
      Vec2 uv;
      EXPECT_TRUE(camera_.project((truth(step.record.t) * T_BS_).inverse() * p_W, &uv));
      step.observations.push_back({id, uv + offset, Vec3::UnitZ(), 0});
    }
    return step;
  }
  CameraModel camera_;
  Pose T_BS_;
};

TEST_F(TrackGeometry, ExactProjectionsScoreZeroAndAnOffsetShows) {
  const auto truth_fn = [](Timestamp t) { return truth(t); };
  const std::vector<std::pair<int, Vec3>> points = {{1, Vec3(4.0, 0.5, 1.2)}, {2, Vec3(5.0, 1.5, 2.0)}};
  TrackGeometryChecker exact(camera_, T_BS_, truth_fn);
  for (int k = 0; k < 6; ++k) exact.add(image(k, points));
  FeatureTruthSummary s = exact.summary();
  EXPECT_EQ(s.landmarks, 2);
  EXPECT_EQ(s.all.count, 12);
  EXPECT_LT(s.all.rms, 1e-6);
  EXPECT_DOUBLE_EQ(s.track_mean, 6.0);
  EXPECT_DOUBLE_EQ(s.observations_per_image, 2.0);

  TrackGeometryChecker moved(camera_, T_BS_, truth_fn);
  for (int k = 0; k < 6; ++k) moved.add(image(k, points, k == 3 ? Vec2(2.0, 0.0) : Vec2::Zero()));
  s = moved.summary();
  EXPECT_GT(s.all.rms, 0.3);
  EXPECT_GT(s.all.p90, 1.0);

  // Two images, or no motion between the images: nothing is scored.
  TrackGeometryChecker short_track(camera_, T_BS_, truth_fn);
  for (int k = 0; k < 2; ++k) short_track.add(image(k, points));
  EXPECT_EQ(short_track.summary().all.count, 0);
  TrackGeometryChecker still(camera_, T_BS_, [](Timestamp) { return truth(0); });
  for (int k = 0; k < 6; ++k) {
    ImageStep step = image(0, points);
    step.record.t = fromSeconds(0.1 * k);
    still.add(step);
  }
  EXPECT_EQ(still.summary().all.count, 0);
}

}  // namespace
}  // namespace hdvio
