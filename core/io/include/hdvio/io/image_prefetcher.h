#pragma once
// Decodes a sequence's images on one I/O thread, a few ahead of the estimator, so that PNG
// decoding leaves the estimator's thread. The consumer takes the images strictly in order;
// what it gets does not depend on timing (a decoding error is re-thrown at that image, in the
// consumer's thread), so runs stay deterministic.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/core/sequence.h"

namespace hdvio::io {

class ImagePrefetcher {
 public:
  using Decoder = std::function<cv::Mat(const ImageRef&)>;
  // decode defaults to loadImage. ahead: how many decoded images may wait (at least 1).
  explicit ImagePrefetcher(std::vector<ImageRef> images, std::size_t ahead = 4,
                           Decoder decode = nullptr);
  ~ImagePrefetcher();
  ImagePrefetcher(const ImagePrefetcher&) = delete;
  ImagePrefetcher& operator=(const ImagePrefetcher&) = delete;

  // The next image in sequence order; blocks until it is decoded. Re-throws its decoding error.
  // Throws std::logic_error past the last image.
  cv::Mat take();
  // Seconds take() spent waiting for the I/O thread, in total.
  double waitSeconds() const { return wait_s_; }

 private:
  struct Slot {
    cv::Mat pixels;
    std::exception_ptr error;
  };
  void work();

  const std::vector<ImageRef> images_;
  const std::size_t ahead_;
  const Decoder decode_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Slot> ready_;
  std::size_t taken_ = 0;
  bool stop_ = false;
  double wait_s_ = 0.0;
  std::thread worker_;  // last: starts after every member above exists
};

}  // namespace hdvio::io
