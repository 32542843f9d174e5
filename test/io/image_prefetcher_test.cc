// The I/O thread that decodes images ahead: images come out in sequence order whatever the
// decoder's timing, an error surfaces at its image in the consumer, and stopping early is clean.
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "hdvio/core/error.h"
#include "hdvio/io/image_prefetcher.h"

namespace hdvio::io {
namespace {

std::vector<ImageRef> refs(int n) {
  std::vector<ImageRef> out;
  for (int i = 0; i < n; ++i) out.push_back({i * 50'000'000LL, "img" + std::to_string(i) + ".png"});
  return out;
}

// A 1x1 image holding the index, decoded with uneven delays.
cv::Mat slowDecode(const ImageRef& r) {
  const int i = static_cast<int>(r.t / 50'000'000LL);
  std::this_thread::sleep_for(std::chrono::microseconds(200 * ((i * 7) % 5)));
  return cv::Mat(1, 1, CV_8UC1, cv::Scalar(i));
}

TEST(ImagePrefetcher, ImagesComeInSequenceOrder) {
  ImagePrefetcher p(refs(40), 3, slowDecode);
  for (int i = 0; i < 40; ++i) {
    if (i % 9 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a slow consumer
    const cv::Mat m = p.take();
    ASSERT_EQ(m.at<unsigned char>(0, 0), i);
  }
  EXPECT_THROW(p.take(), std::logic_error);
}

TEST(ImagePrefetcher, DecodingErrorIsThrownAtItsImage) {
  const auto decode = [](const ImageRef& r) {
    if (r.path == "img5.png") throw InputError(r.path, 0, "cannot read image");
    return slowDecode(r);
  };
  ImagePrefetcher p(refs(10), 2, decode);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(p.take().at<unsigned char>(0, 0), i);
  try {
    p.take();
    FAIL() << "image 5 should throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("img5.png"), std::string::npos) << e.what();
  }
  EXPECT_EQ(p.take().at<unsigned char>(0, 0), 6);  // the next images are still fine
}

TEST(ImagePrefetcher, StopsCleanlyBeforeTheEnd) {
  for (int run = 0; run < 20; ++run) {
    ImagePrefetcher p(refs(100), 4, slowDecode);
    EXPECT_EQ(p.take().at<unsigned char>(0, 0), 0);
  }  // the destructor must not wait for the remaining 99 images, nor hang
}

}  // namespace
}  // namespace hdvio::io
