// One pipeline stage: packets submitted by the stage upstream are handled in submission order,
// either inline on the submitting thread (sequential mode) or on the stage's own thread behind a
// bounded queue (threaded mode). Both modes hand the handler the same packets in the same order,
// so a deterministic handler gives the same results threaded or not; waitHandled() is the defined
// point at which a downstream result is taken back upstream.
//
// A handler that throws stops the stage: later packets are discarded, and submit(),
// waitHandled() and finish() rethrow the first exception on the calling thread.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "rgbdi/common/bounded_queue.h"

namespace rgbdi {

template <class Packet>
class StageWorker {
 public:
  using Handler = std::function<void(Packet&)>;

  StageWorker(std::string name, Handler handler, bool threaded, std::size_t capacity)
      : name_(std::move(name)), handler_(std::move(handler)), queue_(capacity) {
    if (threaded) thread_ = std::thread([this] { run(); });
  }
  ~StageWorker() {
    try {
      finish();
    } catch (...) {
      // Destruction during stack unwinding: the error was (or will be) reported elsewhere.
    }
  }
  StageWorker(const StageWorker&) = delete;
  StageWorker& operator=(const StageWorker&) = delete;

  const std::string& name() const { return name_; }
  bool threaded() const { return thread_.joinable() || finished_threaded_; }

  /// Hands a packet to the stage (blocks while its queue is full in threaded mode).
  void submit(Packet packet) {
    rethrowIfFailed();
    ++submitted_;
    if (!thread_.joinable()) {
      handle(packet);
      rethrowIfFailed();
      return;
    }
    if (!queue_.push(std::move(packet)))
      throw std::logic_error(name_ + ": packet submitted after the stage finished");
  }

  /// Blocks until at least `count` packets have been handled (or the stage failed: rethrows).
  void waitHandled(std::uint64_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return handled_ >= count || error_; });
    lock.unlock();
    rethrowIfFailed();
  }
  std::uint64_t handled() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return handled_;
  }
  std::uint64_t submitted() const { return submitted_; }
  std::size_t queueHighWater() const { return queue_.highWater(); }

  /// Handles everything submitted, stops the thread, rethrows a handler failure.
  void finish() {
    queue_.shutdown();
    if (thread_.joinable()) {
      thread_.join();
      finished_threaded_ = true;
    }
    rethrowIfFailed();
  }

 private:
  void run() {
    Packet p;
    while (queue_.pop(p)) handle(p);
  }
  void handle(Packet& p) {
    bool failed;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      failed = static_cast<bool>(error_);
    }
    if (!failed) {
      try {
        handler_(p);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = std::current_exception();
      }
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++handled_;
    }
    done_.notify_all();
  }
  void rethrowIfFailed() {
    std::exception_ptr e;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      e = error_;
    }
    if (e) std::rethrow_exception(e);
  }

  std::string name_;
  Handler handler_;
  BoundedQueue<Packet> queue_;
  std::thread thread_;
  bool finished_threaded_ = false;
  mutable std::mutex mutex_;
  std::condition_variable done_;
  std::uint64_t handled_ = 0;
  std::uint64_t submitted_ = 0;  // producer side only
  std::exception_ptr error_;
};

}  // namespace rgbdi
