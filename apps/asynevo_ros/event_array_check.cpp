#include "event_array_check.hpp"

#include <fmt/format.h>

namespace asynevo::ros_node {

const char* skipReasonName(SkipReason reason) {
  switch (reason) {
    case SkipReason::kNone:
      return "none";
    case SkipReason::kDecodeError:
      return "decode_error";
    case SkipReason::kEmpty:
      return "empty";
    case SkipReason::kSizeMismatch:
      return "size_mismatch";
    case SkipReason::kOutOfSensor:
      return "out_of_sensor";
    case SkipReason::kBadTime:
      return "bad_time";
    case SkipReason::kUnsorted:
      return "unsorted";
    case SkipReason::kTimeBackwards:
      return "time_backwards";
    case SkipReason::kCount:
      break;
  }
  return "?";
}

namespace {

CheckResult skip(SkipReason reason, std::string message) {
  CheckResult r;
  r.reason = reason;
  r.message = std::move(message);
  return r;
}

}  // namespace

CheckResult checkEventArray(const dvs_msgs::EventArray& msg, const StreamState& state) {
  if (!msg.decode_error.empty()) return skip(SkipReason::kDecodeError, msg.decode_error);
  if (msg.events.empty()) return skip(SkipReason::kEmpty, "the message has no events");
  const bool states_size = msg.width != 0 || msg.height != 0;
  if (states_size &&
      (msg.width != static_cast<uint32_t>(state.width) || msg.height != static_cast<uint32_t>(state.height)))
    return skip(SkipReason::kSizeMismatch,
                fmt::format("the message is for a {}x{} sensor but the calibration is {}x{}", msg.width,
                            msg.height, state.width, state.height));
  CheckResult r;
  r.events.resize(msg.events.size());
  int64_t previous = state.last_t_ns;
  bool has_previous = state.has_last;
  for (std::size_t i = 0; i < msg.events.size(); ++i) {
    const dvs_msgs::Event& in = msg.events[i];
    if (in.x >= state.width || in.y >= state.height)
      return skip(SkipReason::kOutOfSensor,
                  fmt::format("event {} at pixel ({}, {}) is outside the {}x{} sensor", i, in.x, in.y,
                              state.width, state.height));
    if (in.ts.nsec >= 1000000000u)
      return skip(SkipReason::kBadTime,
                  fmt::format("event {} has a nanosecond field of {} (>= 10^9)", i, in.ts.nsec));
    int64_t t = static_cast<int64_t>(in.ts.sec) * 1000000000 + static_cast<int64_t>(in.ts.nsec);
    if (has_previous && t < previous) {
      if (previous - t <= state.max_time_reversal_ns) {
        t = previous;
        ++r.clamped;
      } else if (i == 0) {
        return skip(SkipReason::kTimeBackwards,
                    fmt::format("the first event (t = {} ns) is {:.6f} s earlier than the last accepted one",
                                t, static_cast<double>(previous - t) * 1e-9));
      } else {
        return skip(
            SkipReason::kUnsorted,
            fmt::format("event {} (t = {} ns) is earlier than event {} (t = {} ns)", i, t, i - 1, previous));
      }
    }
    previous = t;
    has_previous = true;
    Event& out = r.events[i];
    out.t_ns = t;
    out.x = in.x;
    out.y = in.y;
    out.polarity = in.polarity != 0 ? 1 : -1;
  }
  return r;
}

}  // namespace asynevo::ros_node
