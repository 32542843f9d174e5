#pragma once
// Image pyramid by 2x2 averaging (SVO's half-sampling) and the bilinear lookups every
// alignment step uses. Level l has pixel coordinates px_level0 / 2^l.
#include <vector>

#include <opencv2/core.hpp>

namespace hdvio::frontend {

using Pyramid = std::vector<cv::Mat>;  // CV_8UC1, level 0 = full resolution

// Throws InputError for an empty or non-8-bit single channel image.
Pyramid buildPyramid(const cv::Mat& image, int levels);
cv::Mat halfSample(const cv::Mat& image);

// Bilinear intensity at (u, v); the caller guarantees 0 <= u < cols-1, 0 <= v < rows-1.
inline float interpolate(const cv::Mat& img, float u, float v) {
  const int x = static_cast<int>(u), y = static_cast<int>(v);
  const float a = u - x, b = v - y;
  const int stride = static_cast<int>(img.step.p[0]);
  const unsigned char* p = img.data + y * stride + x;
  return (1.f - a) * (1.f - b) * p[0] + a * (1.f - b) * p[1] + (1.f - a) * b * p[stride] +
         a * b * p[stride + 1];
}

}  // namespace hdvio::frontend
