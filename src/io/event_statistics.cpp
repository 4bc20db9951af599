#include "asynevo/io/event_statistics.hpp"

#include <algorithm>
#include <vector>

#include "asynevo/core/time.hpp"

namespace asynevo {

double EventStatistics::durationSeconds() const { return asynevo::durationSeconds(first_t_ns, last_t_ns); }

EventStatistics computeEventStatistics(EventReader& reader, int64_t window_ns,
                                       const std::function<void(uint64_t, int64_t)>& progress) {
  EventStatistics stats;
  stats.window_ns = window_ns;
  const int width = reader.info().width;
  std::vector<uint32_t> pixel_counts(static_cast<std::size_t>(width) * reader.info().height, 0);
  std::vector<uint64_t> window_counts;  // one entry per window since the first event (8 B per 10 ms)
  EventPacket packet;
  while (reader.read(packet)) {
    if (stats.events == 0) stats.first_t_ns = packet.frontTime();
    for (const Event& e : packet.events) {
      stats.on_events += e.polarity > 0;
      ++pixel_counts[static_cast<std::size_t>(e.y) * width + e.x];
      const auto window = static_cast<std::size_t>((e.t_ns - stats.first_t_ns) / window_ns);
      if (window >= window_counts.size()) window_counts.resize(window + 1, 0);
      ++window_counts[window];
    }
    stats.events += packet.size();
    stats.last_t_ns = packet.backTime();
    if (progress) progress(stats.events, stats.last_t_ns);
  }
  stats.clamped_times = reader.stats().clamped_times;
  for (uint32_t c : pixel_counts) {
    stats.active_pixels += c > 0;
    stats.max_pixel_events = std::max<uint64_t>(stats.max_pixel_events, c);
  }
  if (stats.events == 0) return stats;
  const double duration = stats.durationSeconds();
  stats.mean_rate = duration > 0 ? static_cast<double>(stats.events) / duration : 0;
  const double window_s = nsToSeconds(window_ns);
  const auto max_it = std::max_element(window_counts.begin(), window_counts.end());
  stats.max_window_rate = static_cast<double>(*max_it) / window_s;
  stats.max_window_start_ns = stats.first_t_ns + (max_it - window_counts.begin()) * window_ns;
  std::vector<uint64_t> sorted = window_counts;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  stats.median_window_rate = static_cast<double>(sorted[sorted.size() / 2]) / window_s;
  return stats;
}

}  // namespace asynevo
