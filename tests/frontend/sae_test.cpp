#include "asynevo/frontend/sae.hpp"

#include <gtest/gtest.h>

namespace asynevo::frontend {
namespace {

Event ev(int64_t t, int x, int y, int p) {
  return Event{t, static_cast<uint16_t>(x), static_cast<uint16_t>(y), static_cast<int8_t>(p)};
}

TEST(Sae, StartsNeverFiredAndAcceptsAnEventAtTimeZero) {
  SurfaceOfActiveEvents sae(10, 8, 50'000'000);
  EXPECT_EQ(sae.saeAt(0, 3, 4), kNever);
  EXPECT_EQ(sae.saeAt(1, 3, 4), kNever);
  EXPECT_TRUE(sae.update(ev(0, 3, 4, +1)));  // the references (maps at 0) would drop this event
  EXPECT_EQ(sae.saeAt(1, 3, 4), 0);
  EXPECT_EQ(sae.saeAt(0, 3, 4), kNever);
  EXPECT_EQ(sae.latestAt(1, 3, 4), 0);
}

TEST(Sae, RefractoryFilterSuppressesSamePolarityBurstsButAlwaysUpdatesLatest) {
  SurfaceOfActiveEvents sae(10, 8, 50);
  EXPECT_TRUE(sae.update(ev(100, 1, 1, +1)));
  EXPECT_FALSE(sae.update(ev(120, 1, 1, +1)));  // within 50 ns
  EXPECT_EQ(sae.saeAt(1, 1, 1), 100);
  EXPECT_EQ(sae.latestAt(1, 1, 1), 120);
  EXPECT_FALSE(sae.update(ev(160, 1, 1, +1)));  // 40 after the latest: still refractory
  EXPECT_TRUE(sae.update(ev(211, 1, 1, +1)));   // quiet for > 50
  EXPECT_EQ(sae.saeAt(1, 1, 1), 211);
  // A polarity flip re-arms the pixel at once.
  EXPECT_TRUE(sae.update(ev(215, 1, 1, -1)));
  EXPECT_TRUE(sae.update(ev(220, 1, 1, +1)));
  EXPECT_EQ(sae.saeAt(1, 1, 1), 220);
  // Other pixels are independent.
  EXPECT_EQ(sae.saeAt(1, 2, 1), kNever);
}

TEST(Sae, CornersOfTheSensorAreAddressable) {
  SurfaceOfActiveEvents sae(240, 180, 0);
  EXPECT_TRUE(sae.update(ev(5, 239, 179, -1)));
  EXPECT_TRUE(sae.update(ev(6, 0, 0, -1)));
  EXPECT_EQ(sae.saeAt(0, 239, 179), 5);
  EXPECT_EQ(sae.saeAt(0, 0, 0), 6);
  sae.clear();
  EXPECT_EQ(sae.saeAt(0, 0, 0), kNever);
}

}  // namespace
}  // namespace asynevo::frontend
