#include "asynevo/frontend/haste_tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

namespace asynevo::frontend {
namespace {

// Events of an L-shaped corner (two edges of length 20 leaving the corner along +x and +y) whose
// corner moves at constant velocity; integer pixels like a sensor.
struct MovingCorner {
  float x0, y0, vx, vy;  // px and px/s
  float length = 20.f;   // edge length, px
  std::mt19937 rng{7};
  float cornerX(int64_t t) const { return x0 + vx * float(t) * 1e-9f; }
  float cornerY(int64_t t) const { return y0 + vy * float(t) * 1e-9f; }
  void next(int64_t t, float& x, float& y) {
    std::uniform_real_distribution<float> along(0.f, length);
    std::normal_distribution<float> noise(0.f, 0.4f);
    const float a = along(rng);
    const bool horizontal = (rng() & 1u) != 0;
    x = std::round(cornerX(t) + (horizontal ? a : 0.f) + noise(rng));
    y = std::round(cornerY(t) + (horizontal ? 0.f : a) + noise(rng));
  }
};

void expectIncrementalEqualsFromScratch(HasteVariant variant) {
  HasteParams params;
  params.variant = variant;
  params.template_update = 0.0;  // the star approximation is exact only with a frozen template
  auto tracker = makeHasteTracker(params);
  MovingCorner corner{100.f, 80.f, 300.f, -150.f};
  tracker->reset(0, 105.f, 85.f);
  int checked = 0, switches = 0;
  double worst = 0;
  for (int64_t i = 0; i < 6000; ++i) {
    const int64_t t = i * 10'000;  // 100 k events/s
    float x, y;
    corner.next(t, x, y);
    const TrackerResult r = tracker->push(t, x, y);
    if (r == TrackerResult::kStateChanged) ++switches;
    if (!tracker->initialized() || r == TrackerResult::kOutOfRange) continue;
    const auto scratch = hasteScoresFromScratch(*tracker);
    for (int h = 0; h < HasteTracker::kHypotheses; ++h) {
      const double err = std::abs(tracker->scores()[h] - scratch[h]) / std::max(1e-9, std::abs(scratch[h]));
      worst = std::max(worst, err);
    }
    ++checked;
  }
  EXPECT_GT(checked, 3000);
  EXPECT_GT(switches, 10);  // the sequence exercises rebuilds after switches, too
  EXPECT_LT(worst, 1e-5) << "largest relative difference " << worst;
}

TEST(Haste, DifferenceStarIncrementalScoresEqualFromScratchScores) {
  expectIncrementalEqualsFromScratch(HasteVariant::kDifferenceStar);
}

TEST(Haste, CorrelationStarIncrementalScoresEqualFromScratchScores) {
  expectIncrementalEqualsFromScratch(HasteVariant::kCorrelationStar);
}

TEST(Haste, InitializesAfterAFullWindowOfInRangeEvents) {
  auto tracker = makeHasteTracker(HasteParams{});
  tracker->reset(1000, 50.f, 50.f);
  EXPECT_FALSE(tracker->initialized());
  EXPECT_EQ(tracker->push(5, 50.f + 15.f, 50.f), TrackerResult::kOutOfRange);  // radius is strict
  EXPECT_EQ(tracker->push(5, 80.f, 50.f), TrackerResult::kOutOfRange);
  MovingCorner corner{46.f, 46.f, 0.f, 0.f, 10.f};
  for (int i = 0; i < HasteTracker::kWindow - 1; ++i) {
    float x, y;
    corner.next(i, x, y);
    ASSERT_EQ(tracker->push(2000 + i, x, y), TrackerResult::kInitializing) << i;
  }
  float x, y;
  corner.next(0, x, y);
  EXPECT_EQ(tracker->push(2000 + HasteTracker::kWindow - 1, x, y), TrackerResult::kStateChanged);
  EXPECT_TRUE(tracker->initialized());
  EXPECT_TRUE(tracker->healthy());
  EXPECT_EQ(tracker->state().t_ns, 2000 + HasteTracker::kMiddle);  // the middle event's time
  EXPECT_FLOAT_EQ(tracker->state().x, 50.f);
  double mass = 0;
  for (float v : tracker->normalizedTemplate()) mass += v;
  EXPECT_NEAR(mass, 1.0, 1e-5);
}

void expectFollowsMovingCorner(HasteVariant variant) {
  HasteParams params;
  params.variant = variant;
  auto tracker = makeHasteTracker(params);
  MovingCorner corner{60.f, 70.f, 400.f, 250.f};  // 40 px in x, 25 px in y over 0.1 s
  tracker->reset(0, 64.f, 74.f);
  int state_changes = 0;
  double worst_after_init = 0;
  for (int64_t i = 0; i < 40000; ++i) {
    const int64_t t = i * 2'500;  // 400 k events/s, 0.1 s
    float x, y;
    corner.next(t, x, y);
    if (tracker->push(t, x, y) != TrackerResult::kStateChanged) continue;
    ++state_changes;
    // The tracked point keeps its offset (4, 4) from the corner, evaluated at the state's time.
    const TrackerState& s = tracker->state();
    const double ex = s.x - (corner.cornerX(s.t_ns) + 4.f), ey = s.y - (corner.cornerY(s.t_ns) + 4.f);
    worst_after_init = std::max(worst_after_init, std::hypot(ex, ey));
  }
  EXPECT_GT(state_changes, 50);
  EXPECT_LT(worst_after_init, 2.0);
  EXPECT_LT(std::abs(tracker->state().theta), 0.2f);
}

TEST(Haste, DifferenceStarFollowsAMovingCorner) { expectFollowsMovingCorner(HasteVariant::kDifferenceStar); }
TEST(Haste, CorrelationStarFollowsAMovingCorner) {
  expectFollowsMovingCorner(HasteVariant::kCorrelationStar);
}

TEST(Haste, StaticPatternNeverSwitchesAndThetaIsWrapped) {
  auto tracker = makeHasteTracker(HasteParams{});
  tracker->reset(0, 50.f, 50.f, 3.0f * 3.14159265f);
  EXPECT_GT(tracker->state().theta, -3.1416f);
  EXPECT_LE(tracker->state().theta, 3.1416f);
  for (const Hypothesis& h : tracker->hypotheses()) {
    EXPECT_GT(h.theta, -3.1416f);
    EXPECT_LE(h.theta, 3.1416f);
  }
  // The same few pixels over and over: the window becomes stationary, no hypothesis is better.
  int changes = 0;
  for (int i = 0; i < 3000; ++i) {
    const float x = 50.f + float(i % 5), y = 50.f + float((i / 5) % 3);
    if (tracker->push(i, x, y) == TrackerResult::kStateChanged) ++changes;
  }
  EXPECT_EQ(changes, 1);  // initialization only
  EXPECT_FLOAT_EQ(tracker->state().x, 50.f);
  for (double s : tracker->scores()) EXPECT_TRUE(std::isfinite(s));
}

TEST(Haste, AnisotropySeparatesEdgesFromCorners) {
  auto edge = makeHasteTracker(HasteParams{});
  auto corner_tracker = makeHasteTracker(HasteParams{});
  edge->reset(0, 50.f, 50.f);
  corner_tracker->reset(0, 50.f, 50.f);
  MovingCorner corner{46.f, 46.f, 0.f, 0.f, 10.f};
  std::mt19937 rng(3);
  for (int i = 0; i < HasteTracker::kWindow; ++i) {
    edge->push(i, 50.f + float(int(rng() % 25) - 12), 50.f + float(rng() % 2));
    float x, y;
    corner.next(i, x, y);
    corner_tracker->push(i, x, y);
  }
  EXPECT_LT(edge->windowAnisotropy(), 0.02f);
  EXPECT_GT(corner_tracker->windowAnisotropy(), 0.15f);
}

// The drift test's reference: the first window's normalized template, matched with the correlation score.
TEST(Haste, FirstTemplateIsTheFirstWindowsAndMatchScoreIsTheCorrelationScore) {
  HasteParams params;  // HasteCorrelation*, template updates on
  auto tracker = makeHasteTracker(params);
  MovingCorner corner{100.f, 80.f, 200.f, 100.f};
  tracker->reset(0, 105.f, 85.f);
  int64_t t = 0;
  while (!tracker->initialized()) {
    float x, y;
    corner.next(t, x, y);
    tracker->push(t, x, y);
    t += 10'000;
  }
  EXPECT_EQ(tracker->firstTemplate(), tracker->normalizedTemplate());
  for (int i = 0; i < 3000; ++i, t += 10'000) {
    float x, y;
    corner.next(t, x, y);
    tracker->push(t, x, y);
  }
  EXPECT_GT(tracker->stateChanges(), 5u);  // it moved, and its current template is no longer the first
  EXPECT_NE(tracker->firstTemplate(), tracker->normalizedTemplate());
  const auto scratch = hasteScoresFromScratch(*tracker);
  for (int h = 0; h < HasteTracker::kHypotheses; ++h) {
    const Hypothesis& hy = tracker->hypotheses()[h];
    EXPECT_NEAR(tracker->matchScore(tracker->normalizedTemplate(), hy.x, hy.y, hy.theta), scratch[h],
                1e-5 * std::abs(scratch[h]));
  }
}

// A tracker that cannot move (hysteresis 1: no switch is ever good enough) while its pattern, a compact
// 7x7 px blot of events, jumps by (3, -2) px: its window now matches the first template that far from its
// state, which the drift test must report; before the jump the drift is 0.
TEST(Haste, FirstTemplateDriftMeasuresHowFarTheWindowIsFromTheState) {
  HasteParams params;
  params.hysteresis = 1.0;
  auto tracker = makeHasteTracker(params);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(0, 6);
  float bx = 98.f, by = 80.f;
  tracker->reset(0, 101.f, 83.f);
  int64_t t = 0;
  auto feed = [&](int n) {
    for (int i = 0; i < n; ++i, t += 10'000) tracker->push(t, bx + float(cell(rng)), by + float(cell(rng)));
  };
  feed(1000);
  ASSERT_TRUE(tracker->initialized());
  EXPECT_EQ(tracker->firstTemplateDrift(), 0.f);
  bx += 3.f;
  by -= 2.f;
  feed(1000);
  EXPECT_EQ(tracker->state().x, 101.f);  // it did not follow
  EXPECT_EQ(tracker->state().y, 83.f);
  EXPECT_NEAR(tracker->firstTemplateDrift(), std::hypot(3.f, 2.f), 0.01f);
}

// A tracker seeded at (105, 85) on a corner at (100, 80) that it cannot follow: hysteresis 1 keeps the
// state where it was seeded, template update 0 keeps the first window's template.
struct StaticCornerTracker {
  explicit StaticCornerTracker(HasteVariant variant) {
    HasteParams params;
    params.variant = variant;
    params.hysteresis = 1.0;
    params.template_update = 0.0;
    tracker = makeHasteTracker(params);
    tracker->reset(0, 105.f, 85.f);
  }
  /// n events of the corner, 10 us apart.
  void feed(int n) {
    for (int i = 0; i < n; ++i, t += 10'000) {
      float x, y;
      corner.next(t, x, y);
      tracker->push(t, x, y);
    }
  }
  std::unique_ptr<HasteTracker> tracker;
  MovingCorner corner{100.f, 80.f, 0.f, 0.f};
  int64_t t = 0;
};

TEST(Haste, SubpixelOffsetFollowsAShiftSmallerThanOnePixel) {
  for (const HasteVariant variant : {HasteVariant::kCorrelationStar, HasteVariant::kDifferenceStar}) {
    StaticCornerTracker fixture(variant);
    MovingCorner& corner = fixture.corner;
    HasteTracker* tracker = fixture.tracker.get();
    auto feed = [&](int n) { fixture.feed(n); };
    feed(2000);
    ASSERT_TRUE(tracker->initialized());
    float dx0 = 1.f, dy0 = 1.f;
    tracker->subpixelOffset(dx0, dy0);
    // With the corner where the template saw it the offset is small (a window of 193 noisy events).
    EXPECT_LT(std::abs(dx0), 0.15f) << "variant " << static_cast<int>(variant);
    EXPECT_LT(std::abs(dy0), 0.15f);
    // The corner moves by (+0.4, -0.4) px: the state cannot follow, the sub-pixel offset does (the
    // parabola through bilinear-sampled scores under-reads a shift: "pixel locking").
    corner.x0 += 0.4f;
    corner.y0 -= 0.4f;
    feed(2000);
    EXPECT_EQ(tracker->state().x, 105.f);
    float dx = 0.f, dy = 0.f;
    tracker->subpixelOffset(dx, dy);
    std::printf("variant %d: offset (%.3f, %.3f) before, (%.3f, %.3f) after a (0.4, -0.4) px shift\n",
                static_cast<int>(variant), dx0, dy0, dx, dy);
    // Measured: x moves by 0.40, y by 0.15-0.17 (the parabola under-reads, more so across the
    // corner's horizontal edge): the direction is right, the size only roughly.
    EXPECT_NEAR(dx - dx0, 0.4f, 0.2f) << "variant " << static_cast<int>(variant);
    EXPECT_LT(dy - dy0, -0.1f) << "variant " << static_cast<int>(variant);
    EXPECT_GT(dy - dy0, -0.6f) << "variant " << static_cast<int>(variant);
  }
}

// The continuous fit (subpixel_method template_fit) reads the same shift with less of the parabola's
// pixel locking. Measured: (0.405, -0.270) against the parabola's (0.40, -0.15); the y shift of the
// horizontal edge is partly lost in the rounding of its events to whole rows.
TEST(Haste, SubpixelFitReadsAShiftSmallerThanOnePixel) {
  for (const HasteVariant variant : {HasteVariant::kCorrelationStar, HasteVariant::kDifferenceStar}) {
    StaticCornerTracker fixture(variant);
    MovingCorner& corner = fixture.corner;
    HasteTracker* tracker = fixture.tracker.get();
    auto feed = [&](int n) { fixture.feed(n); };
    float dx = 1.f, dy = 1.f;
    EXPECT_FALSE(tracker->subpixelFit(dx, dy));  // not initialized: no template
    EXPECT_EQ(dx, 0.f);
    feed(2000);
    ASSERT_TRUE(tracker->initialized());
    float dx0, dy0, px0, py0;
    ASSERT_TRUE(tracker->subpixelFit(dx0, dy0));
    tracker->subpixelOffset(px0, py0);
    EXPECT_LT(std::hypot(dx0, dy0), 0.1f) << "variant " << static_cast<int>(variant);
    corner.x0 += 0.4f;
    corner.y0 -= 0.4f;
    feed(2000);
    float px, py;
    ASSERT_TRUE(tracker->subpixelFit(dx, dy));
    tracker->subpixelOffset(px, py);
    std::printf("variant %d: shift (0.4, -0.4) px read as (%.3f, %.3f) by the fit, (%.3f, %.3f) by the parabola\n",
                static_cast<int>(variant), dx - dx0, dy - dy0, px - px0, py - py0);
    EXPECT_NEAR(dx - dx0, 0.4f, 0.1f) << "variant " << static_cast<int>(variant);
    EXPECT_LT(dy - dy0, -0.2f) << "variant " << static_cast<int>(variant);
    EXPECT_GT(dy - dy0, -0.5f) << "variant " << static_cast<int>(variant);
    EXPECT_LT(std::abs(dy - dy0 + 0.4f), std::abs(py - py0 + 0.4f) - 0.05f) << "variant " << static_cast<int>(variant);
    // A shift of 1.5 px that the state cannot follow (hysteresis 1) is still read: the fit is not limited
    // to the +-0.5 px of the parabola.
    corner.x0 += 1.1f;
    feed(2000);
    ASSERT_TRUE(tracker->subpixelFit(dx, dy));
    EXPECT_NEAR(dx - dx0, 1.5f, 0.15f) << "variant " << static_cast<int>(variant);
  }
}

}  // namespace
}  // namespace asynevo::frontend
