#pragma once
// Noise filters in front of the SAE, the detector and the trackers (docs/frontend.md, "Sensor noise"):
//
//  * BackgroundActivityFilter — the nearest-neighbour background-activity filter of Delbruck
//    ("Frame-free dynamic digital vision", Intl. Symp. on Secure-Life Electronics, 2008; jAER's
//    BackgroundActivityFilter; surveyed by Guo & Delbruck, "Low cost and latency event camera background
//    activity denoising", TPAMI 2023): an event passes when one of its 8 neighbours had an event, of
//    either polarity, within `window_ns` before it. Background activity is uncorrelated in space, so its
//    events rarely have such support; a moving edge fires neighbouring pixels within microseconds to
//    milliseconds. Every event, passed or not, becomes support for its neighbours.
//  * HotPixelFilter — pixels that fire far above their neighbours (a sensor defect: a hot pixel fires at a
//    steady rate whatever the scene does) are found once per `window_ns` of event time and masked for
//    the rest of the stream. A pixel is hot when, in one window, its count reaches `min_rate_hz` and
//    exceeds `factor` times the mean count of its 8 neighbours (plus one); a moving edge or texture
//    fires neighbouring pixels alike, so they never pass this test together.
// Both are O(1) per event and allocate only at construction.

#include <cstdint>
#include <utility>
#include <vector>

namespace asynevo::frontend {

class BackgroundActivityFilter {
 public:
  BackgroundActivityFilter(int width, int height, int64_t window_ns);

  /// Whether the event at (x, y, t) has support; records it as support for its neighbours either way.
  /// The caller guarantees x < width, y < height and non-decreasing t.
  bool pass(int x, int y, int64_t t_ns) {
    const int64_t since = t_ns - window_ns_;
    // The map has a one-pixel border of "never" so the 8 neighbours need no bounds checks.
    const std::size_t stride = static_cast<std::size_t>(width_) + 2;
    const std::size_t i = (static_cast<std::size_t>(y) + 1) * stride + static_cast<std::size_t>(x) + 1;
    const int64_t* up = &last_[i - stride];
    const int64_t* row = &last_[i];
    const int64_t* down = &last_[i + stride];
    const bool supported = up[-1] >= since || up[0] >= since || up[1] >= since || row[-1] >= since ||
                           row[1] >= since || down[-1] >= since || down[0] >= since || down[1] >= since;
    last_[i] = t_ns;
    return supported;
  }

 private:
  int width_;
  int64_t window_ns_;
  std::vector<int64_t> last_;  ///< (width + 2) x (height + 2), time of each pixel's latest event
};

class HotPixelFilter {
 public:
  HotPixelFilter(int width, int height, int64_t window_ns, double factor, double min_rate_hz);

  /// False for an event of a masked pixel. Counts the event; at the end of each window (event time)
  /// looks for new hot pixels. The caller guarantees x < width, y < height and non-decreasing t.
  bool pass(int x, int y, int64_t t_ns) {
    if (t_ns >= window_end_ns_) closeWindow(t_ns);
    const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
    if (masked_[i]) return false;
    ++counts_[i];
    return true;
  }

  /// Masked pixels (x, y), in the order they were found.
  const std::vector<std::pair<int, int>>& hotPixels() const { return hot_; }

 private:
  void closeWindow(int64_t t_ns);

  int width_, height_;
  int64_t window_ns_;
  double factor_;
  uint32_t min_count_;
  int64_t window_end_ns_ = INT64_MIN;
  std::vector<uint32_t> counts_;  ///< events per pixel in the current window
  std::vector<uint8_t> masked_;
  std::vector<std::pair<int, int>> hot_;
};

}  // namespace asynevo::frontend
