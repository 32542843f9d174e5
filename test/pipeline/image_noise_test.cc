// Seeded image noise (run.image_noise_sigma): reproducible per (seed, stamp), different across
// seeds and stamps, of the requested spread, rounded and saturated to 8 bits.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "hdvio/pipeline/visual_sequence_runner.h"

namespace hdvio {
namespace {

int differingPixels(const cv::Mat& a, const cv::Mat& b) { return cv::countNonZero(a != b); }

TEST(ImageNoise, ReproducibleAndSeeded) {
  const cv::Mat gray(120, 160, CV_8UC1, cv::Scalar(128));
  const Timestamp t = 1'234'567'890;
  const cv::Mat a = withImageNoise(gray, 2.0, 1, t);
  EXPECT_EQ(differingPixels(a, withImageNoise(gray, 2.0, 1, t)), 0);
  EXPECT_GT(differingPixels(a, withImageNoise(gray, 2.0, 2, t)), gray.total() / 2);
  EXPECT_GT(differingPixels(a, withImageNoise(gray, 2.0, 1, t + 50'000'000)), gray.total() / 2);
  EXPECT_EQ(a.type(), CV_8UC1);
  EXPECT_EQ(a.size(), gray.size());
}

TEST(ImageNoise, HasTheRequestedSpreadAndSaturates) {
  const cv::Mat gray(200, 200, CV_8UC1, cv::Scalar(100));
  cv::Mat diff;
  withImageNoise(gray, 3.0, 5, 0).convertTo(diff, CV_64F);
  diff -= 100.0;
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  // Rounding adds 1/12 gray level^2 of variance: sqrt(9 + 1/12) = 3.014.
  EXPECT_NEAR(sd[0], 3.014, 0.05);
  double lo = 0, hi = 0;
  cv::minMaxLoc(withImageNoise(cv::Mat(50, 50, CV_8UC1, cv::Scalar(254)), 3.0, 5, 0), &lo, &hi);
  EXPECT_EQ(hi, 255.0);  // saturated, not wrapped around to small values
  EXPECT_GT(lo, 200.0);
}

}  // namespace
}  // namespace hdvio
