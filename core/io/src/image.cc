#include "hdvio/io/image.h"

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/error.h"

namespace hdvio::io {

cv::Mat loadImage(const ImageRef& image) {
  cv::Mat pixels;
  try {
    pixels = cv::imread(image.path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw InputError(image.path, 0, std::string("cannot decode image: ") + e.what());
  }
  if (pixels.empty()) throw InputError(image.path, 0, "cannot read image (missing or not a valid image file)");
  if (pixels.type() != CV_8UC1) pixels.convertTo(pixels, CV_8U);
  return pixels;
}

}  // namespace hdvio::io
