#include "asynevo/eval/association.hpp"

#include <gtest/gtest.h>

namespace asynevo::eval {
namespace {

constexpr int64_t kMs = 1'000'000;

std::vector<std::pair<std::size_t, std::size_t>> pairs(const std::vector<Match>& m) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& x : m) out.emplace_back(x.est, x.gt);
  return out;
}

using P = std::vector<std::pair<std::size_t, std::size_t>>;

TEST(Associate, ClosestPairWinsAndEachPoseIsUsedOnce) {
  // gt at 10 ms: est 0 is 10 ms away, est 1 (15 ms) is 5 ms away -> est 1 gets it, est 0 gets nothing.
  EXPECT_EQ(pairs(associate(std::vector<int64_t>{0, 15 * kMs}, std::vector<int64_t>{10 * kMs})), (P{{1, 0}}));
  // Greedy by |dt|, not per estimate: est 0 would prefer gt 1 (2 ms), but est 1 takes gt 1 (1 ms)
  // first; est 0 then falls back to gt 0 (8 ms).
  EXPECT_EQ(
      pairs(associate(std::vector<int64_t>{10 * kMs, 13 * kMs}, std::vector<int64_t>{2 * kMs, 12 * kMs})),
      (P{{0, 0}, {1, 1}}));
}

TEST(Associate, MaxDifferenceIsStrict) {
  EXPECT_TRUE(associate(std::vector<int64_t>{0}, std::vector<int64_t>{20 * kMs}).empty());
  EXPECT_EQ(associate(std::vector<int64_t>{0}, std::vector<int64_t>{20 * kMs - 1}).size(), 1u);
  EXPECT_EQ(associate(std::vector<int64_t>{0}, std::vector<int64_t>{50 * kMs}, 60 * kMs).size(), 1u);
}

TEST(Associate, TiesGoToTheLowerEstimateIndexThenGroundTruthIndex) {
  // Both estimates are 5 ms from the single gt pose: Python's tuple sort picks est 0.
  EXPECT_EQ(pairs(associate(std::vector<int64_t>{5 * kMs, 15 * kMs}, std::vector<int64_t>{10 * kMs})),
            (P{{0, 0}}));
  // One estimate equally far from two gt poses: gt 0.
  EXPECT_EQ(pairs(associate(std::vector<int64_t>{10 * kMs}, std::vector<int64_t>{5 * kMs, 15 * kMs})),
            (P{{0, 0}}));
}

TEST(Associate, ResultIsOrderedByEstimateAndSkipsUnmatched) {
  const std::vector<int64_t> est = {0, 100 * kMs, 200 * kMs, 300 * kMs};
  const std::vector<int64_t> gt = {1 * kMs, 199 * kMs, 305 * kMs, 400 * kMs};
  EXPECT_EQ(pairs(associate(est, gt)), (P{{0, 0}, {2, 1}, {3, 2}}));
}

TEST(Associate, MatchesBruteForceOnIrregularRates) {
  // Estimate at ~33 Hz with jitter, ground truth at 200 Hz: compare with the all-pairs definition.
  std::vector<int64_t> est, gt;
  for (int i = 0; i < 300; ++i) est.push_back(i * 30 * kMs + (i % 7) * 1'234'567);
  for (int i = 0; i < 2000; ++i) gt.push_back(i * 5 * kMs + (i % 3) * 777);
  const auto fast = associate(est, gt);
  struct C {
    int64_t d;
    std::size_t a, b;
  };
  std::vector<C> all;
  for (std::size_t a = 0; a < est.size(); ++a)
    for (std::size_t b = 0; b < gt.size(); ++b) {
      const int64_t d = std::llabs(est[a] - gt[b]);
      if (d < 20 * kMs) all.push_back({d, a, b});
    }
  std::sort(all.begin(), all.end(),
            [](const C& x, const C& y) { return std::tie(x.d, x.a, x.b) < std::tie(y.d, y.a, y.b); });
  std::vector<bool> ua(est.size()), ub(gt.size());
  P brute;
  for (const C& c : all) {
    if (ua[c.a] || ub[c.b]) continue;
    ua[c.a] = ub[c.b] = true;
    brute.emplace_back(c.a, c.b);
  }
  std::sort(brute.begin(), brute.end());
  EXPECT_EQ(pairs(fast), brute);
  EXPECT_EQ(fast.size(), est.size());
}

}  // namespace
}  // namespace asynevo::eval
