#pragma once
// Time helpers. Every struct stores int64 nanoseconds; double seconds appear only for Δt arithmetic
// and at file boundaries (DESIGN.md §3).

#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace asynevo {

constexpr int64_t kNsPerSecond = 1'000'000'000;
constexpr int64_t kNsPerMillisecond = 1'000'000;
constexpr int64_t kNsPerMicrosecond = 1'000;

/// Seconds (double) to nanoseconds, rounded to the nearest nanosecond.
inline int64_t secondsToNs(double seconds) { return std::llround(seconds * 1e9); }
/// Nanoseconds to seconds. Exact for |t| < 2^53 ns (about 104 days).
inline double nsToSeconds(int64_t t_ns) { return static_cast<double>(t_ns) * 1e-9; }
/// Duration between two timestamps in seconds, computed in integers first so no precision is lost.
inline double durationSeconds(int64_t from_ns, int64_t to_ns) { return nsToSeconds(to_ns - from_ns); }
inline constexpr int64_t millisecondsToNs(int64_t ms) { return ms * kNsPerMillisecond; }
inline constexpr int64_t microsecondsToNs(int64_t us) { return us * kNsPerMicrosecond; }

/// Parses a decimal number of seconds ("2.0971340", "0.6367649989999999", "12", "-0.5", "1e-3")
/// into nanoseconds, rounding half away from zero at the nanosecond. Decimal digits are converted
/// exactly (no binary floating-point step) unless an exponent is present. Returns nullopt when the
/// text is not a finite number. `text` must not contain surrounding white space.
std::optional<int64_t> parseSecondsToNs(std::string_view text);

/// Formats nanoseconds as seconds with 9 decimals ("2.097134000"), exact, for writing files.
void formatNsAsSeconds(int64_t t_ns, char* buffer /* >= 32 bytes */);

}  // namespace asynevo
