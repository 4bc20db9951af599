#include "asynevo/eval/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace asynevo::eval {
namespace {

TEST(Stats, HandComputed) {
  const Stats s = computeStats({4, 1, 3, 2});
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);           // mean of the two middle values, as numpy
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std (ddof = 0), as numpy
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_EQ(s.num_samples, 4u);
  EXPECT_DOUBLE_EQ(computeStats({5, 1, 3}).median, 3);
}

TEST(Stats, EmptyHasNoSamples) {
  const Stats s = computeStats({});
  EXPECT_EQ(s.num_samples, 0u);
  EXPECT_EQ(s.rmse, 0.0);
}

TEST(Percentile, LinearInterpolationLikeNumpy) {
  EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5}, 95), 4.8);  // rank 0.95·4 = 3.8
  EXPECT_DOUBLE_EQ(percentile({5, 1, 2, 4, 3}, 50), 3);
  EXPECT_DOUBLE_EQ(percentile({7}, 95), 7);
  EXPECT_DOUBLE_EQ(percentile({1, 3}, 100), 3);
  EXPECT_DOUBLE_EQ(percentile({1, 3}, 0), 1);
  EXPECT_EQ(percentile({}, 50), 0.0);
}

}  // namespace
}  // namespace asynevo::eval
