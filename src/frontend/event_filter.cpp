#include "asynevo/frontend/event_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asynevo::frontend {

namespace {
constexpr int64_t kNeverNs = std::numeric_limits<int64_t>::min() / 4;
}

BackgroundActivityFilter::BackgroundActivityFilter(int width, int height, int64_t window_ns)
    : width_(width),
      window_ns_(window_ns),
      last_((static_cast<std::size_t>(width) + 2) * (static_cast<std::size_t>(height) + 2), kNeverNs) {}

HotPixelFilter::HotPixelFilter(int width, int height, int64_t window_ns, double factor, double min_rate_hz)
    : width_(width),
      height_(height),
      window_ns_(window_ns),
      factor_(factor),
      min_count_(static_cast<uint32_t>(std::max(1.0, std::ceil(min_rate_hz * static_cast<double>(window_ns) * 1e-9)))),
      counts_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0),
      masked_(counts_.size(), 0) {}

void HotPixelFilter::closeWindow(int64_t t_ns) {
  if (window_end_ns_ != INT64_MIN) {
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
        const uint32_t c = counts_[i];
        if (c < min_count_ || masked_[i]) continue;
        double sum = 0;
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
            sum += counts_[static_cast<std::size_t>(ny) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(nx)];
            ++n;
          }
        }
        if (static_cast<double>(c) > factor_ * (sum / std::max(n, 1) + 1.0)) {
          masked_[i] = 1;
          hot_.emplace_back(x, y);
        }
      }
    }
    std::fill(counts_.begin(), counts_.end(), 0u);
  }
  // The next window starts at this event (a gap in the stream does not leave empty windows behind).
  window_end_ns_ = t_ns + window_ns_;
}

}  // namespace asynevo::frontend
