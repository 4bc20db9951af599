#include "asynevo/core/time.hpp"

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

namespace asynevo {

namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }

// Fallback for scientific notation: strtod, then round. Only used for inputs with an exponent.
std::optional<int64_t> parseWithExponent(std::string_view text) {
  const std::string copy(text);
  char* end = nullptr;
  const double seconds = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size() || !std::isfinite(seconds)) return std::nullopt;
  if (std::fabs(seconds) > 9.0e9) return std::nullopt;
  return secondsToNs(seconds);
}

}  // namespace

std::optional<int64_t> parseSecondsToNs(std::string_view text) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  bool negative = false;
  if (i < n && (text[i] == '-' || text[i] == '+')) {
    negative = text[i] == '-';
    ++i;
  }
  int64_t whole = 0;
  int whole_digits = 0;
  while (i < n && isDigit(text[i])) {
    if (whole_digits >= 10) return std::nullopt;  // > 9,999,999,999 s does not fit in int64 ns
    whole = whole * 10 + (text[i] - '0');
    ++whole_digits;
    ++i;
  }
  int64_t frac = 0;
  int frac_digits = 0;
  bool round_up = false;
  if (i < n && text[i] == '.') {
    ++i;
    while (i < n && isDigit(text[i])) {
      if (frac_digits < 9) {
        frac = frac * 10 + (text[i] - '0');
      } else if (frac_digits == 9) {
        round_up = text[i] >= '5';
      }
      ++frac_digits;
      ++i;
    }
  }
  if (whole_digits == 0 && frac_digits == 0) return std::nullopt;
  if (i < n && (text[i] == 'e' || text[i] == 'E')) return parseWithExponent(text);
  if (i != n) return std::nullopt;
  for (int k = frac_digits; k < 9; ++k) frac *= 10;
  if (whole > 9'000'000'000LL) return std::nullopt;
  int64_t ns = whole * kNsPerSecond + frac + (round_up ? 1 : 0);
  return negative ? -ns : ns;
}

void formatNsAsSeconds(int64_t t_ns, char* buffer) {
  const bool negative = t_ns < 0;
  // Work in unsigned magnitude so INT64_MIN does not overflow.
  const uint64_t magnitude = negative ? (~static_cast<uint64_t>(t_ns) + 1) : static_cast<uint64_t>(t_ns);
  std::snprintf(buffer, 32, "%s%llu.%09llu", negative ? "-" : "",
                static_cast<unsigned long long>(magnitude / kNsPerSecond),
                static_cast<unsigned long long>(magnitude % kNsPerSecond));
}

}  // namespace asynevo
