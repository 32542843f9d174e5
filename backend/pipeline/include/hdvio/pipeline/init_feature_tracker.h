#pragma once
// KLT feature tracks for the visual-inertial initialization on images: before the backend has a
// first state the semi-direct frontend has no metric pose to start its map from, so a plain
// pyramidal Lucas-Kanade tracker (OpenCV, forward-backward checked, Shi-Tomasi corners
// replenished every image) produces the 2-D tracks the ViInitializer needs. Deterministic.
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/core/frame_observations.h"

namespace hdvio {

struct InitTrackerOptions {
  int max_features = 150;
  double quality_level = 0.01;    // Shi-Tomasi, relative to the strongest corner
  double min_distance_frac = 0.04;  // between corners, fraction of the image width
  int window_px = 21;             // LK window
  int pyramid_levels = 3;
  double max_forward_backward_px = 1.0;  // tracked back to within this of where it started
  int border_px = 8;              // corners and tracks this far from the image edge
};

class InitFeatureTracker {
 public:
  explicit InitFeatureTracker(InitTrackerOptions options = {});

  // image: 8-bit grayscale, raw (distorted). Returns the tracks seen in this image (landmark id
  // = track id, distorted pixel); ids are never reused. Throws InputError for a non-8-bit image.
  FrameObservations track(Timestamp t, const cv::Mat& image);

 private:
  void detect(const cv::Mat& image);

  InitTrackerOptions options_;
  cv::Mat prev_;
  std::vector<cv::Point2f> points_;
  std::vector<int> ids_;
  int next_id_ = 0;
};

}  // namespace hdvio
