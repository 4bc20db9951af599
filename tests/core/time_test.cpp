#include "asynevo/core/time.hpp"

#include <gtest/gtest.h>

namespace asynevo {
namespace {

TEST(ParseSecondsToNs, ExactDecimalDigits) {
  EXPECT_EQ(parseSecondsToNs("2.097134"), 2'097'134'000);
  EXPECT_EQ(parseSecondsToNs("0"), 0);
  EXPECT_EQ(parseSecondsToNs("12"), 12'000'000'000);
  EXPECT_EQ(parseSecondsToNs(".5"), 500'000'000);
  EXPECT_EQ(parseSecondsToNs("3."), 3'000'000'000);
  EXPECT_EQ(parseSecondsToNs("-0.25"), -250'000'000);
  EXPECT_EQ(parseSecondsToNs("+1.000000001"), 1'000'000'001);
}

TEST(ParseSecondsToNs, RoundsAtTheNanosecond) {
  // A float-printing artefact seen in the ECD slices (shared/data/SOURCES.md).
  EXPECT_EQ(parseSecondsToNs("0.6367649989999999"), 636'764'999);
  EXPECT_EQ(parseSecondsToNs("0.0000000004"), 0);
  EXPECT_EQ(parseSecondsToNs("0.0000000005"), 1);
  EXPECT_EQ(parseSecondsToNs("-0.0000000005"), -1);
}

TEST(ParseSecondsToNs, ScientificNotation) {
  EXPECT_EQ(parseSecondsToNs("1e-3"), 1'000'000);
  EXPECT_EQ(parseSecondsToNs("2.5E2"), 250'000'000'000);
}

TEST(ParseSecondsToNs, RejectsNonNumbers) {
  for (const char* bad : {"", ".", "-", "abc", "1.2.3", "1,5", "nan", "inf", "-inf", "1e", "1 ", " 1",
                          "99999999999", "1e300", "0x10"}) {
    EXPECT_FALSE(parseSecondsToNs(bad).has_value()) << "input '" << bad << "'";
  }
}

TEST(FormatNsAsSeconds, RoundTripsThroughTheParser) {
  char buffer[32];
  for (int64_t t : {int64_t{0}, int64_t{1}, int64_t{2'097'134'000}, int64_t{-250'000'000},
                    int64_t{59'807'000'001}}) {
    formatNsAsSeconds(t, buffer);
    EXPECT_EQ(parseSecondsToNs(buffer), t) << buffer;
  }
  formatNsAsSeconds(2'097'134'000, buffer);
  EXPECT_STREQ(buffer, "2.097134000");
  formatNsAsSeconds(-1, buffer);
  EXPECT_STREQ(buffer, "-0.000000001");
}

TEST(TimeHelpers, Conversions) {
  EXPECT_EQ(secondsToNs(1.5), 1'500'000'000);
  EXPECT_DOUBLE_EQ(nsToSeconds(250'000'000), 0.25);
  EXPECT_DOUBLE_EQ(durationSeconds(1'000'000'000, 1'020'000'000), 0.02);
  EXPECT_EQ(millisecondsToNs(20), 20'000'000);
  EXPECT_EQ(microsecondsToNs(3), 3'000);
}

}  // namespace
}  // namespace asynevo
