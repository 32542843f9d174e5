#pragma once
// FAST-9 corners on several pyramid levels, at most one per grid cell (the best Shi-Tomasi
// score wins) so features spread over the whole image.
#include <vector>

#include <Eigen/Core>

#include "hdvio/frontend/pyramid.h"

namespace hdvio::frontend {

struct DetectorOptions {
  int cell_size = 32;        // grid cell in level-0 pixels
  int levels = 3;            // detect on pyramid levels 0 .. levels-1
  int fast_threshold = 15;   // intensity difference of the segment test
  double min_score = 30.0;   // smallest Shi-Tomasi eigenvalue (mean squared gradient)
  int border = 8;            // keep corners this far (level pixels) from the image edge
};

struct Corner {
  Eigen::Vector2d px;  // level-0 pixel
  int level = 0;
  double score = 0.0;
};

// Cell bookkeeping shared by the detector and the reprojector.
class FeatureGrid {
 public:
  FeatureGrid(int width, int height, int cell_size);
  int cellIndex(const Eigen::Vector2d& px) const;  // -1 outside the image
  int cells() const { return cols_ * rows_; }
  int cellSize() const { return cell_; }

 private:
  int cols_, rows_, cell_;
};

// True if (x, y) passes the 9-of-16 FAST segment test; the caller keeps 3 pixels of border.
bool isFastCorner(const cv::Mat& img, int x, int y, int threshold);
// Smallest eigenvalue of the 8x8 structure tensor at integer level pixel (x, y), per pixel.
double shiTomasiScore(const cv::Mat& img, int x, int y);

// occupied[c] = true marks cells that already hold a tracked feature (size grid.cells()).
std::vector<Corner> detectCorners(const Pyramid& pyramid, const DetectorOptions& options,
                                  const FeatureGrid& grid, const std::vector<bool>& occupied);

}  // namespace hdvio::frontend
