#pragma once
// Test helper: events of bright axis-aligned squares moving at constant velocity on a dark background.
// Each square's edge is a 1-px intensity ramp crossed by kLevels contrast thresholds, so a pixel emits
// kLevels events (ON entering, OFF leaving) when an edge passes it, as a real sensor emits several;
// time steps are small enough that edges move a fraction of a pixel per step.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo::frontend::testing {

struct MovingSquare {
  double x0, y0, size, vx, vy;      // top-left corner at t = 0 (px), side (px), velocity (px/s)
  double t_start = 0, t_end = 1e9;  // visible interval (s)
  /// Brightness level 0..levels at a pixel centre: signed distance to the outline through a 1-px ramp.
  int level(double px, double py, double t, int levels) const {
    if (t < t_start || t >= t_end) return 0;
    const double x = x0 + vx * t, y = y0 + vy * t;
    const double d = std::min(std::min(px - x, x + size - px), std::min(py - y, y + size - py));
    const double ramp = std::clamp(d + 0.5, 0.0, 1.0);
    return static_cast<int>(std::floor(ramp * levels + 1e-9));
  }
  double cornerX(double t) const { return x0 + vx * t; }
  double cornerY(double t) const { return y0 + vy * t; }
};

inline std::vector<Event> simulateSquares(const std::vector<MovingSquare>& squares, int width, int height,
                                          double duration_s, double step_s = 40e-6) {
  std::vector<Event> events;
  constexpr int kLevels = 4;
  std::vector<uint8_t> state(static_cast<std::size_t>(width) * height, 0);
  const int steps = static_cast<int>(duration_s / step_s);
  // The scene at t = 0 is the starting brightness (no burst of events when the squares "appear").
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (const MovingSquare& s : squares)
        state[static_cast<std::size_t>(y) * width + x] =
            std::max<uint8_t>(state[static_cast<std::size_t>(y) * width + x], s.level(x, y, 0.0, kLevels));
  // Only the region the squares sweep can change.
  double bx0 = width, by0 = height, bx1 = 0, by1 = 0;
  for (const MovingSquare& s : squares) {
    for (double t : {0.0, duration_s}) {
      bx0 = std::min(bx0, s.cornerX(t) - 2);
      by0 = std::min(by0, s.cornerY(t) - 2);
      bx1 = std::max(bx1, s.cornerX(t) + s.size + 2);
      by1 = std::max(by1, s.cornerY(t) + s.size + 2);
    }
  }
  const int x_lo = std::max(0, static_cast<int>(bx0)), x_hi = std::min(width - 1, static_cast<int>(bx1));
  const int y_lo = std::max(0, static_cast<int>(by0)), y_hi = std::min(height - 1, static_cast<int>(by1));
  for (int k = 1; k <= steps; ++k) {
    const double t = k * step_s;
    for (int y = y_lo; y <= y_hi; ++y) {
      for (int x = x_lo; x <= x_hi; ++x) {
        int level = 0;
        for (const MovingSquare& s : squares) level = std::max(level, s.level(x, y, t, kLevels));
        uint8_t& st = state[static_cast<std::size_t>(y) * width + x];
        for (; st < level; ++st)
          events.push_back(Event{static_cast<int64_t>(std::llround(t * 1e9)), static_cast<uint16_t>(x),
                                 static_cast<uint16_t>(y), 1});
        for (; st > level; --st)
          events.push_back(Event{static_cast<int64_t>(std::llround(t * 1e9)), static_cast<uint16_t>(x),
                                 static_cast<uint16_t>(y), -1});
      }
    }
  }
  return events;
}

}  // namespace asynevo::frontend::testing
