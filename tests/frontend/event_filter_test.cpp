// Noise filters in front of the frontend: background activity (Delbruck 2008) and hot pixels.
#include "asynevo/frontend/event_filter.hpp"

#include <gtest/gtest.h>

#include <random>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/frontend/frontend.hpp"

namespace asynevo::frontend {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(BackgroundActivityFilter, PassesOnlyEventsWithRecentNeighbourSupport) {
  BackgroundActivityFilter f(20, 10, 5 * kMs);
  EXPECT_FALSE(f.pass(5, 5, 100 * kMs)) << "nothing fired before: no support";
  EXPECT_TRUE(f.pass(6, 5, 101 * kMs)) << "right neighbour 1 ms later";
  EXPECT_TRUE(f.pass(5, 6, 104 * kMs)) << "diagonal neighbour (6,5) fired 3 ms before";
  EXPECT_FALSE(f.pass(9, 9, 104 * kMs)) << "far away";
  EXPECT_FALSE(f.pass(5, 5, 200 * kMs)) << "its neighbours fired 96 ms ago, more than the window";
  EXPECT_FALSE(f.pass(5, 5, 201 * kMs)) << "the pixel's own previous event is no support";
  EXPECT_FALSE(f.pass(7, 7, 202 * kMs)) << "two pixels away is not a neighbour";
}

TEST(BackgroundActivityFilter, WorksAtTheCornersOfTheSensor) {
  BackgroundActivityFilter f(4, 3, 5 * kMs);
  EXPECT_FALSE(f.pass(0, 0, 1 * kMs));
  EXPECT_TRUE(f.pass(1, 1, 2 * kMs));
  EXPECT_FALSE(f.pass(3, 2, 3 * kMs));
  EXPECT_TRUE(f.pass(2, 2, 4 * kMs));
}

TEST(BackgroundActivityFilter, RemovesMostUniformNoiseAndKeepsAMovingEdge) {
  const int w = 240, h = 180;
  BackgroundActivityFilter f(w, h, 5 * kMs);
  // 1 Hz per pixel of uniform background activity for 2 s (~86 k events).
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ux(0, w - 1), uy(0, h - 1);
  std::exponential_distribution<double> gap(1.0 * w * h);
  int noise = 0, noise_passed = 0;
  for (double t = 0; t < 2.0; t += gap(rng)) {
    ++noise;
    noise_passed += f.pass(ux(rng), uy(rng), static_cast<int64_t>(t * 1e9)) ? 1 : 0;
  }
  // A vertical edge sweeping right at 100 px/s: every pixel of a column fires as it passes.
  int edge = 0, edge_passed = 0;
  for (int x = 10; x < 200; ++x) {
    for (int y = 20; y < 160; ++y) {
      ++edge;
      edge_passed += f.pass(x, y, 3'000 * kMs + x * 10 * kMs + y * 1000) ? 1 : 0;
    }
  }
  EXPECT_LT(noise_passed, 0.05 * noise) << noise_passed << " of " << noise << " noise events passed";
  EXPECT_GT(edge_passed, 0.99 * edge) << edge_passed << " of " << edge << " edge events passed";
}

TEST(HotPixelFilter, MasksAPixelFiringAloneAndKeepsBusyTexture) {
  HotPixelFilter f(30, 30, 1000 * kMs, 10.0, 20.0);
  // Window 1 (0..1 s): pixel (3, 4) fires at 200 Hz alone; a 10x10 textured block fires at 200 Hz per
  // pixel together (a moving texture); pixel (20, 20) fires alone at 10 Hz (below the least rate).
  for (int k = 0; k < 200; ++k) {
    const int64_t t = k * 5 * kMs;
    EXPECT_TRUE(f.pass(3, 4, t));
    for (int y = 10; y < 20; ++y)
      for (int x = 10; x < 20; ++x) EXPECT_TRUE(f.pass(x, y, t + 1000));
    if (k % 20 == 0) {
      EXPECT_TRUE(f.pass(20, 20, t + 2000));
    }
  }
  EXPECT_TRUE(f.hotPixels().empty()) << "nothing is decided before the window ends";
  EXPECT_FALSE(f.pass(3, 4, 1001 * kMs)) << "the hot pixel is masked once the window closed";
  EXPECT_TRUE(f.pass(15, 15, 1002 * kMs));
  EXPECT_TRUE(f.pass(20, 20, 1003 * kMs));
  ASSERT_EQ(f.hotPixels().size(), 1u);
  EXPECT_EQ(f.hotPixels()[0], std::make_pair(3, 4));
  EXPECT_FALSE(f.pass(3, 4, 5000 * kMs)) << "masked for the rest of the stream";
}

TEST(FrontendNoise, FiltersCountWhatTheyDropAndADominantPixelIsNamed) {
  FrontendConfig config;
  config.noise_filter = true;
  config.hot_pixel_filter = true;
  Frontend fe(config, 64, 48);
  MeasurementCollector sink;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> ux(0, 63), uy(0, 47);
  int64_t t = 0;
  for (int k = 0; k < 20000; ++k) {  // a hot pixel at (10, 12) and sparse noise, over 2 s
    t += 100'000;
    fe.process(Event{t, 10, 12, 1}, sink);
    if (k % 4 == 0)
      fe.process(Event{t + 1, static_cast<uint16_t>(ux(rng)), static_cast<uint16_t>(uy(rng)), -1}, sink);
  }
  const FrontendStats& s = fe.stats();
  EXPECT_GT(s.dropped_hot_pixel, 9000u) << "the hot pixel is masked after the first 1 s window";
  EXPECT_GT(s.dropped_noise_filter, 4000u);
  ASSERT_EQ(fe.hotPixels().size(), 1u);
  const auto dominant = fe.dominantPixels(0.5, 16);
  ASSERT_EQ(dominant.size(), 1u);
  EXPECT_EQ(dominant[0].x, 10);
  EXPECT_EQ(dominant[0].y, 12);
  EXPECT_GE(dominant[0].events, 20000u) << "its own events, and perhaps a noise event landing on it";
}

TEST(FrontendNoise, ABalancedStreamHasNoDominantPixels) {
  Frontend fe(FrontendConfig{}, 32, 32);
  MeasurementCollector sink;
  for (int k = 0; k < 4096; ++k)
    fe.process(Event{k * 1000, static_cast<uint16_t>(k % 32), static_cast<uint16_t>((k / 32) % 32), 1}, sink);
  EXPECT_TRUE(fe.dominantPixels(0.5, 16).empty());
  EXPECT_EQ(fe.stats().dropped_noise_filter, 0u) << "the filters are off by default";
}

TEST(FrontendNoise, AZeroWindowIsRejectedWithItsKey) {
  FrontendConfig config;
  config.noise_filter_ms = 0;
  try {
    config.validate();
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("frontend.noise_filter_ms"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace asynevo::frontend
