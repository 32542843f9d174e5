#include "hdvio/io/image_prefetcher.h"

#include <chrono>
#include <stdexcept>
#include <utility>

#include "hdvio/io/image.h"

namespace hdvio::io {

ImagePrefetcher::ImagePrefetcher(std::vector<ImageRef> images, std::size_t ahead, Decoder decode)
    : images_(std::move(images)),
      ahead_(ahead < 1 ? 1 : ahead),
      decode_(decode ? std::move(decode) : Decoder([](const ImageRef& r) { return loadImage(r); })),
      worker_([this] { work(); }) {}

ImagePrefetcher::~ImagePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void ImagePrefetcher::work() {
  for (const ImageRef& ref : images_) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || ready_.size() < ahead_; });
      if (stop_) return;
    }
    Slot slot;
    try {
      slot.pixels = decode_(ref);
    } catch (...) {
      slot.error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(slot));
    }
    changed_.notify_all();
  }
}

cv::Mat ImagePrefetcher::take() {
  if (taken_ >= images_.size()) throw std::logic_error("ImagePrefetcher::take: no image left");
  const auto t0 = std::chrono::steady_clock::now();
  Slot slot;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    slot = std::move(ready_.front());
    ready_.pop_front();
  }
  changed_.notify_all();
  ++taken_;
  wait_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (slot.error) std::rethrow_exception(slot.error);
  return slot.pixels;
}

}  // namespace hdvio::io
