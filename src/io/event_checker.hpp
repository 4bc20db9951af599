#pragma once
// The checks every event reader applies to every event, whatever the format: pixel inside the sensor,
// polarity in {-1, 0, 1}, time not going backwards beyond the tolerance (small steps back are clamped
// and counted). Formats differ only in how they name the place of an error (line or record).

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "asynevo/core/event.hpp"
#include "asynevo/io/sensor_size.hpp"

namespace asynevo::io_detail {

class EventChecker {
 public:
  /// `size_origin` names where the size came from in the out-of-sensor message; `size_settable` adds how to
  /// set another size (not for a size a file's header states: a pixel outside it is a damaged file).
  EventChecker(int width, int height, int64_t max_time_reversal_ns, std::string size_origin = "",
               bool size_settable = false)
      : width_(width), height_(height), tolerance_ns_(max_time_reversal_ns > 0 ? max_time_reversal_ns : 0) {
    if (!size_origin.empty()) size_note_ = " (size from " + size_origin + ")";
    if (size_settable) size_note_ += std::string("; ") + kSensorSizeHowTo;
  }

  /// Fills `out` from the raw fields and returns true, or returns false with `error` set.
  /// Polarity 0 is read as OFF (-1).
  bool accept(int64_t t_ns, int64_t x, int64_t y, int64_t polarity, Event& out, std::string& error) {
    if (x < 0 || x >= width_ || y < 0 || y >= height_) {
      error = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
              std::to_string(width_) + "x" + std::to_string(height_) + " sensor" + size_note_;
      return false;
    }
    if (polarity < -1 || polarity > 1) {
      error = "polarity " + std::to_string(polarity) + " is not one of 0, 1, -1";
      return false;
    }
    if (t_ns < last_t_ns_) {
      // The step back in unsigned arithmetic: with times near both ends of int64 (a corrupt file) the
      // signed difference would overflow.
      const uint64_t back = static_cast<uint64_t>(last_t_ns_) - static_cast<uint64_t>(t_ns);
      if (back > static_cast<uint64_t>(tolerance_ns_)) {
        error = fmt::format(
            "time goes backwards by {} ns (tolerance input.max_time_reversal_us = {:g}); the events must be "
            "sorted by time",
            back, static_cast<double>(tolerance_ns_) / 1000.0);
        return false;
      }
      t_ns = last_t_ns_;
      ++clamped_;
    }
    last_t_ns_ = t_ns;
    out.t_ns = t_ns;
    out.x = static_cast<uint16_t>(x);
    out.y = static_cast<uint16_t>(y);
    out.polarity = static_cast<int8_t>(polarity == 1 ? 1 : -1);
    return true;
  }

  uint64_t clamped() const { return clamped_; }

 private:
  int width_;
  int height_;
  int64_t tolerance_ns_;
  std::string size_note_;
  int64_t last_t_ns_ = INT64_MIN;
  uint64_t clamped_ = 0;
};

}  // namespace asynevo::io_detail
