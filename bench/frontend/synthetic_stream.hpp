#pragma once
// A long synthetic event stream for benchmarks: a texture of random bright squares on a dark
// background (smooth 1-px edges, 4 contrast levels per edge crossing) translating along a circle
// under a W x H sensor, plus uniform background noise. Event rate ~ speed x edge density.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo::bench {

/// Texture offset of syntheticStream at time t (s): a texture point at sensor position p(t0) is at
/// p(t0) - (offset(t) - offset(t0)) at time t (exact ground truth for any track).
inline void syntheticOffset(double speed_px_s, double t, double& ox, double& oy) {
  const double radius = 150.0, omega = speed_px_s / radius;
  ox = 200 + radius * std::cos(omega * t) - radius;
  oy = 200 + radius * std::sin(omega * t) * 0.8;
}

inline std::vector<Event> syntheticStream(int width, int height, double duration_s, double speed_px_s,
                                          int squares = 120, uint32_t seed = 1, double step_s = 50e-6) {
  constexpr int kLevels = 4;
  const int tw = width + 400, th = height + 400;  // texture larger than the motion amplitude
  std::vector<float> tex(static_cast<std::size_t>(tw) * th, 0.f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, tw), uy(0, th), us(8, 26);
  for (int k = 0; k < squares * 6; ++k) {  // texture area ~6x the sensor
    const double x0 = ux(rng), y0 = uy(rng), s = us(rng);
    for (int y = std::max(0, int(y0)); y < std::min(th, int(y0 + s) + 1); ++y)
      for (int x = std::max(0, int(x0)); x < std::min(tw, int(x0 + s) + 1); ++x)
        tex[std::size_t(y) * tw + x] = 1.f;
  }
  auto sample = [&](double x, double y) {  // bilinear = 1-px ramp at edges
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int xx, int yy) {
      return tex[std::size_t(std::clamp(yy, 0, th - 1)) * tw + std::clamp(xx, 0, tw - 1)];
    };
    return (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) +
           (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1);
  };
  auto offset = [&](double t, double& ox, double& oy) { syntheticOffset(speed_px_s, t, ox, oy); };
  std::vector<uint8_t> level(static_cast<std::size_t>(width) * height);
  double ox, oy;
  offset(0, ox, oy);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      level[std::size_t(y) * width + x] =
          static_cast<uint8_t>(std::floor(sample(x + ox + 100, y + oy) * kLevels + 1e-9));
  std::vector<Event> events;
  std::uniform_int_distribution<int> rx(0, width - 1), ry(0, height - 1);
  std::uniform_real_distribution<double> u01(0, 1);
  const int steps = static_cast<int>(duration_s / step_s);
  const double noise_per_step = 0.05 * width * height * step_s;  // 0.05 Hz per pixel
  for (int k = 1; k <= steps; ++k) {
    const double t = k * step_s;
    const int64_t t_ns = static_cast<int64_t>(std::llround(t * 1e9));
    offset(t, ox, oy);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const uint8_t l = static_cast<uint8_t>(std::floor(sample(x + ox + 100, y + oy) * kLevels + 1e-9));
        uint8_t& st = level[std::size_t(y) * width + x];
        for (; st < l; ++st) events.push_back(Event{t_ns, uint16_t(x), uint16_t(y), 1});
        for (; st > l; --st) events.push_back(Event{t_ns, uint16_t(x), uint16_t(y), -1});
      }
    }
    if (u01(rng) < noise_per_step) events.push_back(Event{t_ns, uint16_t(rx(rng)), uint16_t(ry(rng)), 1});
  }
  return events;
}

}  // namespace asynevo::bench
