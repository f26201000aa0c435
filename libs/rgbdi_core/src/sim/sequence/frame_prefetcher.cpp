#include "sim/sequence/frame_prefetcher.h"

namespace rgbdi::sim {

FramePrefetcher::FramePrefetcher(std::function<RgbdFrame(std::size_t)> render, std::size_t count,
                                 std::size_t depth)
    : render_(std::move(render)),
      count_(count),
      depth_(depth < 1 ? 1 : depth),
      worker_([this] { run(); }) {}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
  }
  space_.notify_all();
  worker_.join();
}

void FramePrefetcher::run() {
  for (std::size_t i = 0; i < count_; ++i) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return cancelled_ || queue_.size() < depth_; });
      if (cancelled_) return;
    }
    RgbdFrame frame;
    try {
      frame = render_(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
      ready_.notify_all();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(std::move(frame));
    }
    ready_.notify_all();
  }
}

RgbdFrame FramePrefetcher::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return !queue_.empty() || error_; });
  if (queue_.empty()) std::rethrow_exception(error_);
  RgbdFrame frame = std::move(queue_.front());
  queue_.pop_front();
  lock.unlock();
  space_.notify_all();
  return frame;
}

}  // namespace rgbdi::sim
