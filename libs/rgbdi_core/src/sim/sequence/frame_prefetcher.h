// Renders frames 0..n-1 of a sequence on a background thread, a few frames ahead of the
// consumer (bounded queue), so rendering overlaps with whatever the consumer does with the
// previous frame (estimation, PNG encoding, bag writing). Frames are pure functions of their
// index, so the output is identical to rendering in the consumer's thread.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "rgbdi/common/types.h"

namespace rgbdi::sim {

class FramePrefetcher {
 public:
  /// render(i) produces frame i; at most `depth` frames wait in the queue.
  FramePrefetcher(std::function<RgbdFrame(std::size_t)> render, std::size_t count,
                  std::size_t depth);
  /// Stops the worker (after the frame it is rendering) and joins it.
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  /// The next frame in index order; rethrows an exception raised while rendering it.
  RgbdFrame next();

 private:
  void run();

  std::function<RgbdFrame(std::size_t)> render_;
  std::size_t count_, depth_;
  std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<RgbdFrame> queue_;
  std::exception_ptr error_;
  bool cancelled_ = false;
  std::thread worker_;  // last member: starts after everything above is initialised
};

}  // namespace rgbdi::sim
