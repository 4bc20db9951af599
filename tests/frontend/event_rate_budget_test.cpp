// The frontend's peak-rate budget (frontend/event_rate_budget.hpp): what it processes in full, what it
// tracks without detection and what it sheds, decided by event time and counts only.
#include "asynevo/frontend/event_rate_budget.hpp"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <vector>

namespace asynevo::frontend {
namespace {

using Decision = EventRateBudget::Decision;

constexpr int64_t kWindow = 1'000'000;  // 1 ms

/// Decisions for `n` events spread evenly over [t0, t0 + 1 ms).
std::map<Decision, int> feed(EventRateBudget& budget, int64_t t0, int n) {
  std::map<Decision, int> counts;
  for (int i = 0; i < n; ++i) ++counts[budget.admit(t0 + kWindow * i / n)];
  return counts;
}

TEST(EventRateBudget, UnderTheBudgetEverythingIsProcessedInFull) {
  EventRateBudget budget(1e6, kWindow);  // 1 M ev/s: 1000 events per window
  ASSERT_EQ(budget.budget(), 1000u);
  for (int w = 0; w < 5; ++w) {
    auto c = feed(budget, w * kWindow, 1000);
    EXPECT_EQ(c[Decision::kFull], 1000) << w;
  }
  EXPECT_EQ(budget.stride(), 1u);
}

TEST(EventRateBudget, ABurstSkipsDetectionThenShedsEvenly) {
  EventRateBudget budget(1e6, kWindow);
  // First burst window: nothing is shed yet (the stride follows the previous window), the events past
  // the budget skip detection.
  auto c = feed(budget, 0, 6000);
  EXPECT_EQ(c[Decision::kFull], 1000);
  EXPECT_EQ(c[Decision::kTrackOnly], 5000);
  EXPECT_EQ(c[Decision::kShed], 0);
  // Next window: the previous held 6000 > 2 x 1000, so one event in every 3 is kept: 2000 of 6000.
  c = feed(budget, kWindow, 6000);
  EXPECT_EQ(budget.stride(), 3u);
  EXPECT_EQ(c[Decision::kShed], 4000);
  EXPECT_EQ(c[Decision::kFull] + c[Decision::kTrackOnly], 2000);
  EXPECT_EQ(c[Decision::kFull], 333);  // kept events among the window's first 1000
  // The burst ends: a window after a normal one sheds nothing.
  feed(budget, 2 * kWindow, 500);
  c = feed(budget, 3 * kWindow, 500);
  EXPECT_EQ(budget.stride(), 1u);
  EXPECT_EQ(c[Decision::kFull], 500);
}

TEST(EventRateBudget, AWindowAfterASilentGapStartsWithoutShedding) {
  EventRateBudget budget(1e6, kWindow);
  feed(budget, 0, 10000);
  const auto c = feed(budget, 5 * kWindow, 10000);  // 4 ms of silence in between
  EXPECT_EQ(c.count(Decision::kShed), 0u);
  EXPECT_EQ(budget.stride(), 1u);
}

TEST(EventRateBudget, TheSameStreamGetsTheSameDecisions) {
  EventRateBudget a(2e6, kWindow), b(2e6, kWindow);
  std::vector<Decision> da, db;
  for (int i = 0; i < 50000; ++i) {
    const int64_t t = static_cast<int64_t>(i) * i % 7 + i * 200;  // bursty, non-decreasing
    da.push_back(a.admit(t));
    db.push_back(b.admit(t));
  }
  EXPECT_EQ(da, db);
}

TEST(EventRateBudget, RejectsANonPositiveRateOrWindow) {
  EXPECT_THROW(EventRateBudget(0.0, kWindow), std::invalid_argument);
  EXPECT_THROW(EventRateBudget(1e6, 0), std::invalid_argument);
}

}  // namespace
}  // namespace asynevo::frontend
