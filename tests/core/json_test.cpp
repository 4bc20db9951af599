#include "asynevo/core/json.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace asynevo {
namespace {

TEST(Json, QuotesEscapesAndNumbers) {
  EXPECT_EQ(jsonQuoted("a\"b\\c\nd\te\rf\x01"), "\"a\\\"b\\\\c\\nd\\te\\rf\\u0001\"");
  EXPECT_EQ(jsonNumber(0.1), "0.1");
  EXPECT_EQ(jsonNumber(std::nan("")), "null");
  EXPECT_EQ(jsonNumber(1.0 / 0.0), "null");
}

}  // namespace
}  // namespace asynevo
