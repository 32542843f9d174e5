#include "hdvio/io/image.h"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <mutex>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "bag_format.h"
#include "hdvio/core/error.h"
#include "ros_messages.h"

namespace hdvio::io {
namespace {

using Bytes = std::vector<unsigned char>;

// The error names the row that lists the image when there is one: that is where a user fixes it.
[[noreturn]] void fail(const ImageRef& image, const std::string& problem) {
  if (image.list_file.empty()) throw InputError(image.path, 0, problem);
  throw InputError(image.list_file, image.list_line, "image " + image.path + ": " + problem);
}

std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

std::uint32_t crc32(const unsigned char* data, std::size_t n) {
  static const auto table = [] {
    std::vector<std::uint32_t> t(256);
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// libpng decodes a truncated file into a partly grey image with only a warning on stderr, so the
// chunk structure is checked first: every chunk complete with a matching CRC, ending in IEND.
// Returns an empty string when the file is sound, else what is wrong.
std::string pngProblem(const Bytes& b) {
  std::size_t at = 8;
  while (at + 12 <= b.size()) {
    const std::uint32_t length = bigEndian32(&b[at]);
    if (length > b.size() - at - 12) return "truncated PNG (chunk at byte " + std::to_string(at) + " is cut off)";
    const std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    if (crc32(&b[at + 4], length + 4) != bigEndian32(&b[at + 8 + length]))
      return "corrupt PNG (CRC mismatch in " + type + " chunk at byte " + std::to_string(at) + ")";
    at += 12 + length;
    if (type == "IEND") return {};
  }
  return "truncated PNG (no IEND chunk)";
}

bool startsWith(const Bytes& b, std::initializer_list<unsigned char> magic) {
  return b.size() >= magic.size() && std::equal(magic.begin(), magic.end(), b.begin());
}

Bytes readFile(const ImageRef& image) {
  std::ifstream in(image.path, std::ios::binary);
  if (!in) fail(image, "cannot open image file (missing or unreadable)");
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(image, "cannot read image file");
  if (bytes.empty()) fail(image, "image file is empty (0 bytes)");
  return bytes;
}

void silenceOpenCv() {
  static std::once_flag once;
  std::call_once(once, [] { cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT); });
}

// An image file: its bytes checked (a truncated PNG or JPEG is an error, not a grey image), then
// decoded and made grayscale.
cv::Mat decodeFile(const ImageRef& image) {
  const Bytes bytes = readFile(image);
  if (startsWith(bytes, {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'})) {
    const std::string problem = pngProblem(bytes);
    if (!problem.empty()) fail(image, problem);
  } else if (startsWith(bytes, {0xFF, 0xD8})) {
    if (bytes.size() < 4 || bytes[bytes.size() - 2] != 0xFF || bytes[bytes.size() - 1] != 0xD9)
      fail(image, "truncated JPEG (no end-of-image marker)");
  }
  cv::Mat pixels;
  try {
    pixels = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    fail(image, std::string("cannot decode image: ") + e.what());
  }
  if (pixels.empty()) fail(image, "cannot decode image (not a valid image file)");
  if (pixels.depth() != CV_8U)
    fail(image, "expected an 8-bit image, found " + std::to_string(8 * pixels.elemSize1()) + "-bit");
  if (pixels.channels() == 3) cv::cvtColor(pixels, pixels, cv::COLOR_BGR2GRAY);
  else if (pixels.channels() == 4) cv::cvtColor(pixels, pixels, cv::COLOR_BGRA2GRAY);
  else if (pixels.channels() != 1)
    fail(image, "expected a grayscale or color image, found " + std::to_string(pixels.channels()) + " channels");
  return pixels;
}

// An image message inside a ROS bag (ImageRef::span).
cv::Mat decodeBagMessage(const ImageRef& image) {
  std::ifstream in(image.path, std::ios::binary);
  if (!in) fail(image, "cannot open bag");
  const std::string message = bag::readMessage(in, *image.span, image.path);
  return ros::decodeImagePixels(message, image.span->compressed_image, image.path,
                                "image at " + std::to_string(image.t));
}

}  // namespace

cv::Mat loadImage(const ImageRef& image, const CameraCalibration* camera) {
  silenceOpenCv();
  const cv::Mat pixels = image.span ? decodeBagMessage(image) : decodeFile(image);
  if (camera && camera->width > 0 && (pixels.cols != camera->width || pixels.rows != camera->height)) {
    fail(image, "image is " + std::to_string(pixels.cols) + "x" + std::to_string(pixels.rows) + " but " +
                    (camera->file.empty() ? std::string("the camera calibration") : camera->file) + " says " +
                    std::to_string(camera->width) + "x" + std::to_string(camera->height));
  }
  return pixels;
}

std::size_t checkAllImages(const Sequence& sequence) {
  const CameraCalibration* camera = sequence.camera ? &*sequence.camera : nullptr;
  for (const ImageRef& image : sequence.images) loadImage(image, camera);
  return sequence.images.size();
}

}  // namespace hdvio::io
