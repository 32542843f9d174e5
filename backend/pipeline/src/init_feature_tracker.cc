#include "hdvio/pipeline/init_feature_tracker.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "hdvio/core/error.h"

namespace hdvio {

InitFeatureTracker::InitFeatureTracker(InitTrackerOptions options) : options_(options) {}

void InitFeatureTracker::detect(const cv::Mat& image) {
  const int wanted = options_.max_features - static_cast<int>(points_.size());
  if (wanted <= 0) return;
  const double min_distance = std::max(5.0, options_.min_distance_frac * image.cols);
  // Keep new corners away from the existing tracks and the border.
  cv::Mat mask(image.size(), CV_8UC1, cv::Scalar(0));
  const int b = options_.border_px;
  mask(cv::Rect(b, b, image.cols - 2 * b, image.rows - 2 * b)).setTo(255);
  for (const auto& p : points_) cv::circle(mask, p, static_cast<int>(min_distance), 0, -1);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, wanted, options_.quality_level, min_distance, mask);
  for (const auto& c : corners) {
    points_.push_back(c);
    ids_.push_back(next_id_++);
  }
}

FrameObservations InitFeatureTracker::track(Timestamp t, const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC1)
    throw InputError("", 0, "initialization tracker: image is not 8-bit grayscale");
  if (!prev_.empty() && !points_.empty()) {
    std::vector<cv::Point2f> forward, backward;
    std::vector<unsigned char> ok_f, ok_b;
    std::vector<float> err;
    const cv::Size win(options_.window_px, options_.window_px);
    cv::calcOpticalFlowPyrLK(prev_, image, points_, forward, ok_f, err, win,
                             options_.pyramid_levels);
    cv::calcOpticalFlowPyrLK(image, prev_, forward, backward, ok_b, err, win,
                             options_.pyramid_levels);
    const double b = options_.border_px;
    const double max_fb2 = options_.max_forward_backward_px * options_.max_forward_backward_px;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const cv::Point2f d = backward[i] - points_[i];
      const cv::Point2f& p = forward[i];
      if (!ok_f[i] || !ok_b[i] || d.dot(d) > max_fb2 || p.x < b || p.y < b ||
          p.x > image.cols - 1 - b || p.y > image.rows - 1 - b)
        continue;
      points_[kept] = p;
      ids_[kept] = ids_[i];
      ++kept;
    }
    points_.resize(kept);
    ids_.resize(kept);
  } else {
    points_.clear();
    ids_.clear();
  }
  detect(image);
  prev_ = image.clone();
  FrameObservations out{t, {}};
  out.features.reserve(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i)
    out.features.push_back({ids_[i], Eigen::Vector2d(points_[i].x, points_[i].y)});
  return out;
}

}  // namespace hdvio
