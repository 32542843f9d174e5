#include "hdvio/frontend/pyramid.h"

#include "hdvio/core/error.h"

namespace hdvio::frontend {

cv::Mat halfSample(const cv::Mat& in) {
  cv::Mat out(in.rows / 2, in.cols / 2, CV_8UC1);
  for (int y = 0; y < out.rows; ++y) {
    const unsigned char* r0 = in.ptr<unsigned char>(2 * y);
    const unsigned char* r1 = in.ptr<unsigned char>(2 * y + 1);
    unsigned char* o = out.ptr<unsigned char>(y);
    for (int x = 0; x < out.cols; ++x)
      o[x] = static_cast<unsigned char>((r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1] + 2) / 4);
  }
  return out;
}

Pyramid buildPyramid(const cv::Mat& image, int levels) {
  if (image.empty() || image.type() != CV_8UC1)
    throw InputError("", 0, "frontend: image must be a non-empty 8-bit grayscale image");
  if (levels < 1 || (image.cols >> (levels - 1)) < 16 || (image.rows >> (levels - 1)) < 16)
    throw InputError("", 0, "frontend: image too small for " + std::to_string(levels) +
                                " pyramid levels");
  Pyramid pyr;
  pyr.reserve(levels);
  pyr.push_back(image.isContinuous() ? image : image.clone());
  for (int l = 1; l < levels; ++l) pyr.push_back(halfSample(pyr.back()));
  return pyr;
}

}  // namespace hdvio::frontend
