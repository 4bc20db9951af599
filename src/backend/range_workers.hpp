#pragma once
// A few worker threads kept for the length of one window solve, so that each of its evaluations (about
// six per update) hands its ranges to threads already running instead of starting new ones (a thread's
// start costs a few hundred microseconds here, a quarter of an evaluation of 2,500 factors).
//
// run(ranges, fn) calls fn(k) for k = 0 … ranges − 1: k = 0 on the calling thread, the others on the
// workers, and returns when every call has returned. The calls must not throw.

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace asynevo::backend {

class RangeWorkers {
 public:
  /// `workers` threads besides the caller's (0: run() calls everything on the calling thread).
  explicit RangeWorkers(int workers) {
    threads_.reserve(static_cast<std::size_t>(std::max(workers, 0)));
    for (int w = 0; w < workers; ++w) threads_.emplace_back([this, w] { loop(w + 1); });
  }
  RangeWorkers(const RangeWorkers&) = delete;
  RangeWorkers& operator=(const RangeWorkers&) = delete;
  ~RangeWorkers() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  int workers() const { return static_cast<int>(threads_.size()); }

  /// fn(0 … ranges − 1); ranges − 1 must not exceed workers().
  void run(int ranges, const std::function<void(int)>& fn) {
    if (ranges <= 1 || threads_.empty()) {
      for (int k = 0; k < ranges; ++k) fn(k);
      return;
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      fn_ = &fn;
      ranges_ = ranges;
      pending_ = ranges - 1;
      ++generation_;
    }
    wake_.notify_all();
    fn(0);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
    fn_ = nullptr;
  }

 private:
  void loop(int k) {
    unsigned long seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (k >= ranges_) continue;  // fewer ranges than workers this time
      const std::function<void(int)>* fn = fn_;
      lock.unlock();
      (*fn)(k);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(int)>* fn_ = nullptr;
  int ranges_ = 0;
  int pending_ = 0;
  unsigned long generation_ = 0;
  bool stop_ = false;
};

}  // namespace asynevo::backend
