#pragma once
// A bounded blocking FIFO between two threads (docs/pipeline.md §Queue). push() blocks while the queue
// is full, pop() while it is empty; close() wakes both sides: after it, push() refuses new items and
// pop() drains what is left, then reports the end. Waits are counted so a run can tell whether the
// producer was held back by the consumer.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

namespace asynevo::pipeline {

template <class T>
class BoundedQueue {
 public:
  /// Throws std::invalid_argument for a zero capacity.
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {
    if (capacity == 0) throw std::invalid_argument("BoundedQueue: capacity must be at least 1");
  }
  BoundedQueue(const BoundedQueue&) = delete;
  BoundedQueue& operator=(const BoundedQueue&) = delete;

  /// Appends `item`, waiting while the queue is full. Returns false (item dropped) once closed.
  bool push(T item) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (items_.size() >= capacity_ && !closed_) {
      ++push_waits_;
      not_full_.wait(lock, [&] { return items_.size() < capacity_ || closed_; });
    }
    if (closed_) return false;
    items_.push_back(std::move(item));
    if (items_.size() > high_water_) high_water_ = items_.size();
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  /// Appends `item` when there is room; false when full or closed (the item is left untouched).
  bool tryPush(T& item) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (closed_ || items_.size() >= capacity_) return false;
    items_.push_back(std::move(item));
    if (items_.size() > high_water_) high_water_ = items_.size();
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  /// Removes the oldest item, waiting while the queue is empty and open. nullopt: closed and drained.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (items_.empty() && !closed_) {
      ++pop_waits_;
      not_empty_.wait(lock, [&] { return !items_.empty() || closed_; });
    }
    if (items_.empty()) return std::nullopt;
    std::optional<T> item(std::move(items_.front()));
    items_.pop_front();
    lock.unlock();
    not_full_.notify_one();
    return item;
  }

  /// No more pushes; pop() returns the remaining items, then nullopt. Idempotent.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  std::size_t capacity() const { return capacity_; }
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  /// Times push() had to wait for room (the consumer was the bottleneck).
  uint64_t pushWaits() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return push_waits_;
  }
  /// Times pop() had to wait for an item (the producer was the bottleneck).
  uint64_t popWaits() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pop_waits_;
  }
  /// Largest number of items held at once.
  std::size_t highWater() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return high_water_;
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  bool closed_ = false;
  uint64_t push_waits_ = 0, pop_waits_ = 0;
  std::size_t high_water_ = 0;
};

}  // namespace asynevo::pipeline
