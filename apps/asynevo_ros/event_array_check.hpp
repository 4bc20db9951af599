#pragma once
// Checks one received dvs_msgs/EventArray before any of it reaches the pipeline, and converts it to
// AsynEVO events. A message is taken whole or skipped whole: a skipped message is named by its reason
// (a counter per reason) and a sentence for the log. Pure function of the message and the stream's state,
// so it is unit tested without a ROS master (tests/ros/event_array_check_test.cpp).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/core/event.hpp"
#include "dvs_msgs/EventArray.h"

namespace asynevo::ros_node {

enum class SkipReason : std::size_t {
  kNone = 0,
  kDecodeError,    ///< the bytes were not a valid message (cut short, count larger than the message)
  kEmpty,          ///< no events
  kSizeMismatch,   ///< width/height stated by the message differ from the calibration's
  kOutOfSensor,    ///< a pixel outside width x height
  kBadTime,        ///< a nanosecond field of 10^9 or more
  kUnsorted,       ///< an event earlier than the one before it in the message
  kTimeBackwards,  ///< the first event is earlier than the last event already accepted
  kCount
};
constexpr std::size_t kSkipReasons = static_cast<std::size_t>(SkipReason::kCount);

/// The counter name of a reason, as the node's stats and docs/guide/ros.md list them ("empty", ...).
const char* skipReasonName(SkipReason reason);

struct CheckResult {
  SkipReason reason = SkipReason::kNone;
  std::string message;        ///< why it was skipped (empty when accepted)
  std::vector<Event> events;  ///< the converted events when accepted
  uint64_t clamped = 0;       ///< events a little earlier than their predecessor, set to its time
};

/// The sensor and the stream's state the message is checked against.
struct StreamState {
  int width = 0;
  int height = 0;
  bool has_last = false;  ///< an event was accepted before
  int64_t last_t_ns = 0;  ///< the newest accepted event's time
  /// An event earlier than its predecessor by at most this is clamped to the predecessor's time and counted,
  /// as the file readers do (the configuration's input.max_time_reversal_us); a larger step back skips the
  /// message.
  int64_t max_time_reversal_ns = 0;
};

/// Checks `msg` against `state`. A message stating width and height 0 is accepted (some drivers leave the
/// size out); any other size must equal the sensor's. Polarity: 0 is OFF, anything else ON. Time: see
/// StreamState::max_time_reversal_ns.
CheckResult checkEventArray(const dvs_msgs::EventArray& msg, const StreamState& state);

/// Skip counters, one per reason.
using SkipCounters = std::array<uint64_t, kSkipReasons>;

}  // namespace asynevo::ros_node
