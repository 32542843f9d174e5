#include "hdvio/io/image.h"

#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "bag_format.h"
#include "hdvio/core/error.h"
#include "ros_messages.h"

namespace hdvio::io {

cv::Mat loadImage(const ImageRef& image) {
  if (image.span) {  // a message inside a ROS bag
    std::ifstream in(image.path, std::ios::binary);
    if (!in) throw InputError(image.path, 0, "cannot open bag");
    const std::string message = bag::readMessage(in, *image.span, image.path);
    return ros::decodeImagePixels(message, image.span->compressed_image, image.path,
                                  "image at " + std::to_string(image.t));
  }
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
