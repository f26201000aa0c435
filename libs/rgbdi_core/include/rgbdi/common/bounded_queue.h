// A bounded multi-producer / multi-consumer queue joining pipeline stages that run on their own
// threads. push() blocks while the queue is full (back-pressure: offline runs lose nothing),
// tryPush() never blocks (live sources drop instead), pop() blocks while it is empty. shutdown()
// wakes every waiter: pushes fail from then on, pops drain what is queued and then fail.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <stdexcept>

namespace rgbdi {

template <class T>
class BoundedQueue {
 public:
  /// capacity >= 1 (throws std::invalid_argument otherwise).
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {
    if (capacity == 0) throw std::invalid_argument("BoundedQueue: capacity must be at least 1");
  }

  /// Waits for room, then appends. False (value dropped) when the queue was shut down.
  bool push(T value) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return shut_down_ || items_.size() < capacity_; });
    if (shut_down_) return false;
    append(std::move(value));
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  /// Appends when there is room; false when the queue is full or shut down (value untouched).
  bool tryPush(T& value) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (shut_down_ || items_.size() >= capacity_) return false;
    append(std::move(value));
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  /// Waits for an element. False when the queue is shut down and empty.
  bool pop(T& out) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return shut_down_ || !items_.empty(); });
    if (items_.empty()) return false;
    out = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    not_full_.notify_one();
    return true;
  }

  /// Ends the queue: pending and later push() calls fail, pop() drains, then fails.
  void shutdown() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      shut_down_ = true;
    }
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  std::size_t capacity() const { return capacity_; }
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  /// Largest size() seen so far.
  std::size_t highWater() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return high_water_;
  }
  bool isShutDown() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return shut_down_;
  }

 private:
  void append(T&& value) {
    items_.push_back(std::move(value));
    if (items_.size() > high_water_) high_water_ = items_.size();
  }

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  std::size_t high_water_ = 0;
  bool shut_down_ = false;
};

}  // namespace rgbdi
