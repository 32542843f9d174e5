// Every one of the 95 real EuRoC V1_01 excerpt images is tracked without loss.
#include <gtest/gtest.h>

#include <filesystem>

#include "hdvio/io/asl.h"
#include "track_runner.h"

namespace hdvio::frontend {
namespace {

TEST(FrontendEuroc, AllImagesOfV101ExcerptTracked) {
  const std::string folder = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "missing " << folder;
  const Sequence seq = io::readAsl(folder);
  ASSERT_EQ(seq.images.size(), 95u);
  const TrackRunSummary s = runTracking(seq, TrackRunOptions());
  EXPECT_EQ(s.tracked, 95);
  EXPECT_EQ(s.lost, 0);
  EXPECT_EQ(s.reinitializations, 0);
  EXPECT_LE(s.groundtruth_priors, FrontendOptions().bootstrap_max_frames + 1);
  EXPECT_GE(s.min_features, 60);
  // The drone hovers during these 4.7 s; the frontend alone must not drift away from it.
  for (const TrackedFrame& f : s.frames) {
    ASSERT_TRUE(f.groundtruth_T_WB.has_value());
    EXPECT_LT((f.result.T_WB.p - f.groundtruth_T_WB->p).norm(), 0.02) << f.result.frame_id;
    EXPECT_LT(quatLog(f.result.T_WB.q.conjugate() * f.groundtruth_T_WB->q).norm() * 180 / M_PI,
              0.5) << f.result.frame_id;
  }
}

}  // namespace
}  // namespace hdvio::frontend

namespace hdvio::frontend {
namespace {

TEST(FrontendEuroc, AllImagesTrackedWithoutAnyGroundTruth) {
  const std::string folder = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "missing " << folder;
  TrackRunOptions options;
  options.groundtruth_bootstrap = false;  // vision and gyroscope only; map up to scale
  const TrackRunSummary s = runTracking(io::readAsl(folder), options);
  EXPECT_EQ(s.tracked, 95);
  EXPECT_EQ(s.reinitializations, 0);
  EXPECT_EQ(s.groundtruth_priors, 0);
  EXPECT_GE(s.min_features, 60);
  // Starting at the identity, the camera must stay put (it hovers) and keep its attitude.
  const Pose first = s.frames.front().result.T_WB;
  const Pose first_gt = *s.frames.front().groundtruth_T_WB;
  for (const TrackedFrame& f : s.frames) {
    const Pose rel = first.inverse() * f.result.T_WB;
    const Pose rel_gt = first_gt.inverse() * *f.groundtruth_T_WB;
    EXPECT_LT(quatLog(rel.q.conjugate() * rel_gt.q).norm() * 180 / M_PI, 0.5) << f.result.frame_id;
    EXPECT_LT(rel.p.norm(), 0.05) << f.result.frame_id;
  }
}

}  // namespace
}  // namespace hdvio::frontend
