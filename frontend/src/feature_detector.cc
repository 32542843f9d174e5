#include "hdvio/frontend/feature_detector.h"

#include <cmath>

#include <opencv2/features2d.hpp>

namespace hdvio::frontend {

FeatureGrid::FeatureGrid(int width, int height, int cell_size)
    : cols_((width + cell_size - 1) / cell_size), rows_((height + cell_size - 1) / cell_size),
      cell_(cell_size) {}

int FeatureGrid::cellIndex(const Eigen::Vector2d& px) const {
  const int c = static_cast<int>(px.x()) / cell_, r = static_cast<int>(px.y()) / cell_;
  if (px.x() < 0 || px.y() < 0 || c >= cols_ || r >= rows_) return -1;
  return r * cols_ + c;
}

namespace {
// Bresenham circle of radius 3, clockwise from the top.
constexpr int kCircle[16][2] = {{0, -3}, {1, -3}, {2, -2}, {3, -1}, {3, 0},  {3, 1},
                                {2, 2},  {1, 3},  {0, 3},  {-1, 3}, {-2, 2}, {-3, 1},
                                {-3, 0}, {-3, -1}, {-2, -2}, {-1, -3}};
}  // namespace

bool isFastCorner(const cv::Mat& img, int x, int y, int threshold) {
  const unsigned char* c = img.ptr<unsigned char>(y) + x;
  const int stride = static_cast<int>(img.step.p[0]);
  const int hi = c[0] + threshold, lo = c[0] - threshold;
  auto at = [&](int i) { return static_cast<int>(c[kCircle[i][1] * stride + kCircle[i][0]]); };
  // Any 9 contiguous pixels contain at least two of the four compass points.
  int bright = 0, dark = 0;
  for (int i = 0; i < 16; i += 4) {
    const int v = at(i);
    bright += v > hi;
    dark += v < lo;
  }
  if (bright < 2 && dark < 2) return false;
  int v[16];
  for (int i = 0; i < 16; ++i) v[i] = at(i);
  for (int sign = 0; sign < 2; ++sign) {
    int run = 0;
    for (int i = 0; i < 16 + 9; ++i) {
      const int p = v[i % 16];
      const bool pass = sign == 0 ? p > hi : p < lo;
      run = pass ? run + 1 : 0;
      if (run >= 9) return true;
    }
  }
  return false;
}

double shiTomasiScore(const cv::Mat& img, int x, int y) {
  // Central differences are half-integers: sum twice the gradients in integers (exact, and
  // vectorizable), then scale; the sums are the same numbers a double loop would add up.
  int sxx = 0, sxy = 0, syy = 0;
  const int stride = static_cast<int>(img.step.p[0]);
  for (int dy = -4; dy < 4; ++dy) {
    const unsigned char* p = img.ptr<unsigned char>(y + dy) + x - 4;
    for (int dx = 0; dx < 8; ++dx, ++p) {
      const int gx = p[1] - p[-1];
      const int gy = p[stride] - p[-stride];
      sxx += gx * gx;
      sxy += gx * gy;
      syy += gy * gy;
    }
  }
  const double a = 0.25 * sxx, b = 0.25 * sxy, c = 0.25 * syy;
  const double n = 64.0;
  return 0.5 * (a + c - std::sqrt((a - c) * (a - c) + 4.0 * b * b)) / n;
}

std::vector<Corner> detectCorners(const Pyramid& pyramid, const DetectorOptions& options,
                                  const FeatureGrid& grid, const std::vector<bool>& occupied) {
  std::vector<Corner> best(grid.cells());
  const int levels = std::min<int>(options.levels, static_cast<int>(pyramid.size()));
  const int border = std::max(options.border, 5);
  std::vector<cv::KeyPoint> candidates;
  for (int level = 0; level < levels; ++level) {
    const cv::Mat& img = pyramid[level];
    const double scale = 1 << level;
    // OpenCV's FAST-9 is the same strict segment test as isFastCorner (checked against it in
    // detector_test) with SIMD; it returns corners row by row, left to right, so the first of
    // equal scores wins as in a raster scan.
    cv::FAST(img, candidates, options.fast_threshold, false, cv::FastFeatureDetector::TYPE_9_16);
    for (const cv::KeyPoint& kp : candidates) {
      const int x = static_cast<int>(kp.pt.x), y = static_cast<int>(kp.pt.y);
      if (x < border || y < border || x >= img.cols - border || y >= img.rows - border) continue;
      const Eigen::Vector2d px(x * scale, y * scale);
      const int cell = grid.cellIndex(px);
      if (cell < 0 || occupied[cell]) continue;
      const double score = shiTomasiScore(img, x, y);
      if (score > best[cell].score) best[cell] = Corner{px, level, score};
    }
  }
  std::vector<Corner> corners;
  for (const Corner& c : best)
    if (c.score > options.min_score) corners.push_back(c);
  return corners;
}

}  // namespace hdvio::frontend
