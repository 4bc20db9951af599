#pragma once
// A one-line progress display on stderr, shown only when stderr is a terminal (quiet in pipes, logs
// and CI). Updates at most every 0.25 s of wall time.

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>

#include "asynevo/core/time.hpp"

namespace asynevo::cli {

class Progress {
 public:
  Progress() : enabled_(isatty(fileno(stderr)) != 0), start_(Clock::now()), last_(start_) {}
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// `events` processed so far, the current event time and the stream's first event time; `lag_ns`
  /// (optional, < 0 = not shown) how far the backend is behind the newest event time.
  void update(uint64_t events, int64_t t_ns, int64_t first_t_ns, int64_t lag_ns = -1) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (now - last_ < std::chrono::milliseconds(250)) return;
    last_ = now;
    const double wall = std::chrono::duration<double>(now - start_).count();
    const double stream = durationSeconds(first_t_ns, t_ns);
    fmt::print(stderr, "\r  {:>12L} events  t = {:.3f} s  {:.1f} M events/s  real-time factor {:.2f}", events,
               nsToSeconds(t_ns), wall > 0 ? static_cast<double>(events) / wall * 1e-6 : 0.0,
               stream > 0 ? wall / stream : 0.0);
    if (lag_ns >= 0) fmt::print(stderr, "  backend lag {:.2f} s", nsToSeconds(lag_ns));
    fmt::print(stderr, "   ");
    shown_ = true;
  }
  void finish() {
    if (shown_) fmt::print(stderr, "\n");
    shown_ = false;
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  bool shown_ = false;
  Clock::time_point start_, last_;
};

}  // namespace asynevo::cli
