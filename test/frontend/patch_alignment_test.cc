// Feature alignment: 2-D Lucas-Kanade on an affinely warped reference patch.
#include <gtest/gtest.h>

#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/patch_alignment.h"
#include "synthetic_room.h"

namespace hdvio::frontend {
namespace {

TEST(FrontendPatchAlignment, FindsShiftedPatchWithBrightnessChange) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const test::SyntheticRoom room;
  const Pose T = test::lookingForward(Vec3(0, 0, 1.5), 0.0, 0.2);
  cv::Mat ref = room.render(camera, T);
  // Current image: the reference shifted by (3, -2) pixels and 12 levels brighter.
  cv::Mat cur(ref.size(), CV_8UC1, cv::Scalar(0));
  for (int y = 2; y < ref.rows - 3; ++y)
    for (int x = 0; x < ref.cols - 3; ++x)
      cur.at<unsigned char>(y, x + 3) = cv::saturate_cast<unsigned char>(ref.at<unsigned char>(y + 2, x) + 12);
  const FeatureGrid grid(ref.cols, ref.rows, 64);
  const Pyramid pyr = buildPyramid(ref, 3);
  int converged = 0, accurate = 0, tried = 0;
  DetectorOptions level0;
  level0.levels = 1;
  for (const Corner& c : detectCorners(pyr, level0, grid, std::vector<bool>(grid.cells(), false))) {
    if (c.level != 0 || c.px.x() < 20 || c.px.y() < 20 || c.px.x() > 730 || c.px.y() > 460) continue;
    ++tried;
    BorderedPatch patch;
    ASSERT_TRUE(warpPatch(Eigen::Matrix2d::Identity(), ref, c.px, 0, 0, &patch));
    Vec2 px = c.px + Vec2(1.5, 0.5);  // initial guess off by (1.5, 2.5) from the truth
    if (!align2D(cur, patch, 20, &px)) continue;
    ++converged;
    accurate += (px - (c.px + Vec2(3, -2))).norm() < 0.1;
  }
  ASSERT_GT(tried, 20);
  EXPECT_GT(converged, 0.9 * tried);
  EXPECT_GT(accurate, 0.9 * tried);
}

// The current image is the reference sheared and stretched (a surface seen from a new angle
// that the predicted warp, here the identity, does not know): freeing the patch's affine
// distortion finds the true position, translation-only alignment less often.
TEST(FrontendPatchAlignment, AffineAlignmentRecoversTheUnpredictedDistortion) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const test::SyntheticRoom room;
  const Pose T = test::lookingForward(Vec3(0, 0, 1.5), 0.0, 0.2);
  const cv::Mat ref = room.render(camera, T);
  Eigen::Matrix2d S;
  S << 1.1, 0.25, -0.05, 0.95;
  const Vec2 shift(2.0, -1.0);
  cv::Mat M = (cv::Mat_<double>(2, 3) << S(0, 0), S(0, 1), shift.x(), S(1, 0), S(1, 1), shift.y());
  cv::Mat cur;
  cv::warpAffine(ref, cur, M, ref.size(), cv::INTER_LINEAR);
  const FeatureGrid grid(ref.cols, ref.rows, 64);
  const Pyramid pyr = buildPyramid(ref, 3);
  DetectorOptions level0;
  level0.levels = 1;
  int tried = 0, affine_accurate = 0, translation_accurate = 0;
  for (const Corner& c : detectCorners(pyr, level0, grid, std::vector<bool>(grid.cells(), false))) {
    const Vec2 truth = S * c.px + shift;
    if (c.px.x() < 20 || c.px.y() < 20 || truth.x() < 20 || truth.y() < 20 || truth.x() > 730 ||
        truth.y() > 460)
      continue;
    ++tried;
    BorderedPatch patch;
    ASSERT_TRUE(warpPatch(Eigen::Matrix2d::Identity(), ref, c.px, 0, 0, &patch));
    Vec2 px = truth + Vec2(0.8, -0.6);
    if (align2D(cur, patch, 20, &px)) translation_accurate += (px - truth).norm() < 0.2;
    px = truth + Vec2(0.8, -0.6);
    if (align2DAffine(cur, patch, 20, 0.5, &px)) affine_accurate += (px - truth).norm() < 0.2;
  }
  std::printf("%d corners: within 0.2 px %d with the affine distortion free, %d translation only\n",
              tried, affine_accurate, translation_accurate);
  ASSERT_GT(tried, 20);
  EXPECT_GT(affine_accurate, 0.6 * tried);  // 38 of 54 when written
  EXPECT_GT(affine_accurate, translation_accurate + 0.4 * tried);  // translation only: 2
}

TEST(FrontendPatchAlignment, AffineWarpOfPureRotationAboutOpticalAxis) {
  const CameraModel camera(752, 480, 450, 450, 376, 240);
  // Rolling the camera by 30 degrees rotates patches by 30 degrees, whatever the depth.
  const Pose T_cur_ref(quatExp(Vec3(0, 0, M_PI / 6)), Vec3::Zero());
  const Vec2 px(376, 240);
  const Eigen::Matrix2d A = affineWarp(camera, px, camera.unproject(px), 4.0, 0, T_cur_ref);
  Eigen::Matrix2d R;
  R << std::cos(M_PI / 6), -std::sin(M_PI / 6), std::sin(M_PI / 6), std::cos(M_PI / 6);
  EXPECT_LT((A - R).norm(), 1e-6);
  EXPECT_EQ(bestSearchLevel(A, 4), 0);
  EXPECT_EQ(bestSearchLevel(4.0 * A, 4), 2);  // 4x larger patch: two levels up
}

}  // namespace
}  // namespace hdvio::frontend
