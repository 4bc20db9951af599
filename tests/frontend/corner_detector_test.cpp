#include "asynevo/frontend/corner_detector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace asynevo::frontend {
namespace {

// A ring whose newest arc (all equal time 1000) has length k and starts at index `start`
// (wrapping), the rest distinct and older.
std::vector<int64_t> ringWithArc(int n, int k, int start) {
  std::vector<int64_t> ring(n);
  for (int i = 0; i < n; ++i) ring[i] = 10 + 7 * ((i * 5) % n);  // distinct, < 1000
  for (int j = 0; j < k; ++j) ring[(start + j) % n] = 1000;
  return ring;
}

TEST(ArcStar, ArcLengthOfACleanNewestArcAtEveryDecisionBoundary) {
  const ArcCircle& s = smallArcCircle();
  const ArcCircle& l = largeArcCircle();
  struct Case {
    const ArcCircle* c;
    int k;
    bool passes;
  };
  const Case cases[] = {{&s, 3, true},  {&s, 6, true},  {&s, 7, false},  {&s, 9, false},
                        {&s, 10, true}, {&s, 13, true}, {&s, 14, false}, {&s, 16, false},
                        {&l, 4, true},  {&l, 8, true},  {&l, 9, false},  {&l, 11, false},
                        {&l, 12, true}, {&l, 16, true}, {&l, 17, false}, {&l, 20, false}};
  for (const Case& c : cases) {
    for (int start : {0, 1, c.c->n - 2, c.c->n - 1}) {  // includes wrap-around at index 0
      const auto ring = ringWithArc(c.c->n, c.k, start);
      const int length = arcStarLength(ring.data(), c.c->n, c.c->lmin);
      EXPECT_EQ(length, c.k) << "n " << c.c->n << " k " << c.k << " start " << start;
      EXPECT_EQ(arcLengthPasses(length, *c.c), c.passes) << "n " << c.c->n << " k " << c.k;
    }
  }
}

TEST(ArcStar, ShortArcIsForcedToTheMinimumAndAllEqualRingIsFull) {
  const ArcCircle& s = smallArcCircle();
  std::vector<int64_t> ring(16, 0);
  ring[5] = 100;  // single newest pixel, all others equal: the arc grows over the ties
  EXPECT_EQ(arcStarLength(ring.data(), 16, s.lmin), 16);
  std::vector<int64_t> flat(16, kNever);
  EXPECT_EQ(arcStarLength(flat.data(), 16, s.lmin), 16);
  // A single newest pixel among strictly decreasing neighbours: forced to lmin.
  std::vector<int64_t> falling(16);
  for (int i = 0; i < 16; ++i) falling[i] = 100 - std::abs(i - 8) * 3 - (i > 8 ? 1 : 0);
  EXPECT_EQ(arcStarLength(falling.data(), 16, s.lmin), s.lmin);
}

BinaryPatch patchFrom(const char* rows[9]) {
  BinaryPatch p{};
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) p[j * 9 + i] = rows[j][i] == '#' ? 1 : 0;
  return p;
}

TEST(Harris, CanonicalPatches) {
  BinaryPatch zero{};
  EXPECT_DOUBLE_EQ(harrisScore(zero), 0.0);
  BinaryPatch full;
  full.fill(1);
  EXPECT_NEAR(harrisScore(full), 0.0, 1e-12);
  const char* edge[9] = {"####.....", "####.....", "####.....", "####.....", "####.....",
                         "####.....", "####.....", "####.....", "####....."};
  EXPECT_LE(harrisScore(patchFrom(edge)), 1e-9);
  const char* corner[9] = {".........", ".........", ".........", ".........", "....#####",
                           "....#####", "....#####", "....#####", "....#####"};  // 25 pixels, L corner
  const double r = harrisScore(patchFrom(corner));
  EXPECT_GT(r, 8.0);
  // The score is symmetric under transposition and mirroring.
  const char* corner_mirrored[9] = {".........", ".........", ".........", ".........", "#####....",
                                    "#####....", "#####....", "#####....", "#####...."};
  EXPECT_NEAR(harrisScore(patchFrom(corner_mirrored)), r, 1e-9);
  BinaryPatch isolated{};
  isolated[4 * 9 + 4] = 1;
  EXPECT_GT(harrisScore(isolated), 0.0);
  EXPECT_LT(harrisScore(isolated), 8.0);
}

Event ev(int64_t t, int x, int y, int p) {
  return Event{t, static_cast<uint16_t>(x), static_cast<uint16_t>(y), static_cast<int8_t>(p)};
}

// Fires the pixels of the quadrant x >= cx, y >= cy of a 9x9 window (a corner of a square sweeping in),
// older far from the corner, the event at the corner last.
void fireCorner(SurfaceOfActiveEvents& sae, int cx, int cy, int64_t t0) {
  int64_t t = t0;
  for (int d = 8; d >= 0; --d)
    for (int dy = 0; dy <= 4; ++dy)
      for (int dx = 0; dx <= 4; ++dx)
        if (dx + dy == d) sae.update(ev(t += 10, cx + dx, cy + dy, 1));
}

TEST(CornerDetector, StagesOnASyntheticCorner) {
  SurfaceOfActiveEvents sae(40, 30, 1000);
  CornerDetector det(sae, DetectorParams{});
  fireCorner(sae, 20, 15, 0);
  // The corner pixel's event (the newest) is a candidate and a corner.
  EXPECT_TRUE(det.isArcCandidate(1, 20, 15));
  BinaryPatch patch;
  ASSERT_TRUE(det.buildPatch(1, 20, 15, patch));
  int ones = 0;
  for (uint8_t v : patch) ones += v;
  EXPECT_EQ(ones, 25);
  EXPECT_GT(det.harrisAt(1, 20, 15), 8.0);
  const Event e = ev(1'000'000, 20, 15, 1);
  const CornerResult r = det.detect(e, sae.update(e));
  EXPECT_TRUE(r.accepted);
  EXPECT_TRUE(r.candidate);
  EXPECT_TRUE(r.corner);
  EXPECT_GT(r.score, 8.0f);
  // Other polarity channel has nothing.
  EXPECT_FALSE(det.buildPatch(0, 20, 15, patch));
  EXPECT_EQ(det.harrisAt(0, 20, 15), -INFINITY);
}

TEST(CornerDetector, StraightEdgeIsNotACorner) {
  SurfaceOfActiveEvents sae(40, 30, 1000);
  CornerDetector det(sae, DetectorParams{});
  int64_t t = 0;
  for (int x = 10; x <= 30; ++x)  // a vertical edge sweeping right
    for (int y = 5; y < 25; ++y) sae.update(ev(t += 10, x, y, 1));
  EXPECT_LE(det.harrisAt(1, 30, 15), 8.0);
  const Event e = ev(t + 10'000, 30, 15, 1);
  EXPECT_FALSE(det.detect(e, sae.update(e)).corner);
}

TEST(CornerDetector, BorderBandAndFilteredEventsAreNeverCorners) {
  SurfaceOfActiveEvents sae(40, 30, 1000);
  CornerDetector det(sae, DetectorParams{});
  EXPECT_TRUE(det.inBorder(3, 10));
  EXPECT_TRUE(det.inBorder(36, 10));
  EXPECT_FALSE(det.inBorder(35, 25));
  EXPECT_TRUE(det.inBorder(35, 26));
  const Event e = ev(0, 0, 0, 1);
  const CornerResult r = det.detect(e, sae.update(e));
  EXPECT_TRUE(r.accepted);
  EXPECT_FALSE(r.candidate);
  EXPECT_FALSE(det.detect(e, false).accepted);
  // Arc* mode reports candidates as corners without a score.
  DetectorParams arc;
  arc.kind = DetectorKind::kArcStar;
  CornerDetector arc_det(sae, arc);
  fireCorner(sae, 20, 15, 100);
  const Event c = ev(1'000'000, 20, 15, 1);
  const CornerResult rc = arc_det.detect(c, sae.update(c));
  EXPECT_TRUE(rc.corner);
  EXPECT_EQ(rc.score, 0.f);
}

}  // namespace
}  // namespace asynevo::frontend
