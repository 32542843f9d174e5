#include <algorithm>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

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

// The raster scan the detector must equal: every pixel through isFastCorner, best score per cell,
// the first of equal scores kept.
std::vector<Corner> rasterDetect(const Pyramid& pyr, const DetectorOptions& o, const FeatureGrid& grid,
                                 const std::vector<bool>& occupied) {
  std::vector<Corner> best(grid.cells());
  const int border = std::max(o.border, 5);
  for (int level = 0; level < o.levels; ++level) {
    const cv::Mat& img = pyr[level];
    for (int y = border; y < img.rows - border; ++y)
      for (int x = border; x < img.cols - border; ++x) {
        const Eigen::Vector2d px(x * (1 << level), y * (1 << level));
        const int cell = grid.cellIndex(px);
        if (cell < 0 || occupied[cell] || !isFastCorner(img, x, y, o.fast_threshold)) continue;
        const double score = shiTomasiScore(img, x, y);
        if (score > best[cell].score) best[cell] = Corner{px, level, score};
      }
  }
  std::vector<Corner> out;
  for (const Corner& c : best)
    if (c.score > o.min_score) out.push_back(c);
  return out;
}

TEST(FrontendDetector, EqualsTheRasterScanOfTheSegmentTest) {
  cv::Mat img(240, 320, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.2);  // texture with corners at many scores
  img(cv::Rect(100, 60, 80, 70)).setTo(128);         // a flat cell block: no corners there
  const Pyramid pyr = buildPyramid(img, 3);
  const FeatureGrid grid(320, 240, 32);
  std::vector<bool> occupied(grid.cells(), false);
  occupied[3] = occupied[17] = true;
  for (int threshold : {5, 15, 30}) {
    DetectorOptions o;
    o.fast_threshold = threshold;
    o.min_score = 5.0;
    const std::vector<Corner> fast = detectCorners(pyr, o, grid, occupied);
    const std::vector<Corner> ref = rasterDetect(pyr, o, grid, occupied);
    ASSERT_GT(ref.size(), 20u) << threshold;
    ASSERT_EQ(fast.size(), ref.size()) << threshold;
    for (std::size_t i = 0; i < ref.size(); ++i) {
      EXPECT_EQ(fast[i].px, ref[i].px) << threshold << " " << i;
      EXPECT_EQ(fast[i].level, ref[i].level);
      EXPECT_EQ(fast[i].score, ref[i].score);
    }
  }
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
