#pragma once
#include <opencv2/core.hpp>

#include "hdvio/core/sequence.h"

namespace hdvio::io {

// Loads the image as 8-bit grayscale. Throws InputError when the file is missing, empty, not
// 8-bit, truncated or corrupt (PNG: every chunk present with a valid CRC up to IEND; JPEG: ends
// with the EOI marker; then OpenCV must decode it) or, with a camera, when its size differs
// from the calibration. The error names the camera file and the row that lists the image when
// the reader recorded them (ImageRef::list_file), else the image file. OpenCV prints nothing.
cv::Mat loadImage(const ImageRef& image, const CameraCalibration* camera = nullptr);

// Every image of the sequence decoded and checked against its camera calibration; throws at
// the first bad one. Returns the number checked.
std::size_t checkAllImages(const Sequence& sequence);

}  // namespace hdvio::io
