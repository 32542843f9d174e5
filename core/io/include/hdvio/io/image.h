#pragma once
#include <opencv2/core.hpp>

#include "hdvio/core/sequence.h"

namespace hdvio::io {

// Loads the image as 8-bit grayscale; throws InputError naming the file if it cannot be read.
cv::Mat loadImage(const ImageRef& image);

}  // namespace hdvio::io
