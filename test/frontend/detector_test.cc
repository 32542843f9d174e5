#include <gtest/gtest.h>

#include "hdvio/core/error.h"
#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/pyramid.h"

namespace hdvio::frontend {
namespace {

cv::Mat squares() {  // bright squares on a dark background: every square has 4 corners
  cv::Mat img(240, 320, CV_8UC1, cv::Scalar(40));
  for (int y = 20; y + 30 < img.rows; y += 60)
    for (int x = 20; x + 30 < img.cols; x += 60) img(cv::Rect(x, y, 30, 30)).setTo(200);
  return img;
}

TEST(FrontendDetector, FastFiresOnCornersNotOnEdgesOrFlatAreas) {
  const cv::Mat img = squares();
  EXPECT_TRUE(isFastCorner(img, 20, 20, 20));    // top-left corner of the first square
  EXPECT_FALSE(isFastCorner(img, 35, 20, 20));   // middle of its top edge
  EXPECT_FALSE(isFastCorner(img, 35, 35, 20));   // inside
  EXPECT_FALSE(isFastCorner(img, 55, 10, 20));   // background
  EXPECT_GT(shiTomasiScore(img, 20, 20), 100.0);
  EXPECT_LT(shiTomasiScore(img, 35, 35), 1e-9);
}

TEST(FrontendDetector, AtMostOneCornerPerFreeCell) {
  const Pyramid pyr = buildPyramid(squares(), 3);
  const FeatureGrid grid(320, 240, 40);
  std::vector<bool> occupied(grid.cells(), false);
  occupied[0] = true;
  const std::vector<Corner> corners = detectCorners(pyr, DetectorOptions(), grid, occupied);
  ASSERT_GT(corners.size(), 10u);
  std::vector<int> per_cell(grid.cells(), 0);
  for (const Corner& c : corners) {
    const int cell = grid.cellIndex(c.px);
    ASSERT_GE(cell, 0);
    EXPECT_NE(cell, 0);
    EXPECT_EQ(++per_cell[cell], 1);
  }
  EXPECT_TRUE(detectCorners(buildPyramid(cv::Mat(240, 320, CV_8UC1, cv::Scalar(9)), 3),
                            DetectorOptions(), grid, std::vector<bool>(grid.cells(), false))
                  .empty());
}

TEST(FrontendPyramid, HalvesAndAverages) {
  cv::Mat img(64, 96, CV_8UC1);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) img.at<unsigned char>(y, x) = static_cast<unsigned char>((x + y) % 2 ? 100 : 50);
  const Pyramid pyr = buildPyramid(img, 3);
  ASSERT_EQ(pyr.size(), 3u);
  EXPECT_EQ(pyr[2].cols, 24);
  EXPECT_EQ(pyr[2].rows, 16);
  EXPECT_EQ(pyr[1].at<unsigned char>(5, 7), 75);
  EXPECT_NEAR(interpolate(img, 10.5f, 3.0f), 75.0f, 1e-4);
  EXPECT_THROW(buildPyramid(cv::Mat(), 3), InputError);
  EXPECT_THROW(buildPyramid(img, 4), InputError);  // 96 / 8 = 12 pixels is too small
}

}  // namespace
}  // namespace hdvio::frontend
