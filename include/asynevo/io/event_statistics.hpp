#pragma once
// Summary statistics of an event stream, gathered in one streaming pass (bounded memory).

#include <cstdint>
#include <functional>

#include "asynevo/io/event_reader.hpp"

namespace asynevo {

struct EventStatistics {
  uint64_t events = 0;
  uint64_t on_events = 0;
  int64_t first_t_ns = 0;
  int64_t last_t_ns = 0;
  uint64_t clamped_times = 0;
  /// Event rate over fixed windows of `window_ns` (events/s): mean over the span, median and maximum
  /// over the windows (windows without events count as zero).
  int64_t window_ns = 0;
  double mean_rate = 0;
  double median_window_rate = 0;
  double max_window_rate = 0;
  int64_t max_window_start_ns = 0;
  /// Pixels that fired at least once, and the highest per-pixel count (a hot-pixel indicator).
  uint64_t active_pixels = 0;
  uint64_t max_pixel_events = 0;

  double durationSeconds() const;
  double onFraction() const { return events ? static_cast<double>(on_events) / static_cast<double>(events) : 0; }
};

/// Reads `reader` to its end. `progress` (optional) is called after every packet with the events
/// done and the last event time.
EventStatistics computeEventStatistics(EventReader& reader, int64_t window_ns = 10'000'000,
                                       const std::function<void(uint64_t, int64_t)>& progress = {});

}  // namespace asynevo
