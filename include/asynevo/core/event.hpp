#pragma once
// Events and packets of events: the unit of data that flows from readers to the frontend.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace asynevo {

/// One event-camera event. Pixel (0,0) is the top-left pixel centre, x right, y down.
struct Event {
  int64_t t_ns = 0;      ///< timestamp in nanoseconds (sensor time base of the dataset)
  uint16_t x = 0;        ///< column
  uint16_t y = 0;        ///< row
  int8_t polarity = 0;   ///< +1 ON (brightness increase), -1 OFF; file formats' 0 maps to -1

  friend bool operator==(const Event& a, const Event& b) {
    return a.t_ns == b.t_ns && a.x == b.x && a.y == b.y && a.polarity == b.polarity;
  }
};

/// Index of the polarity channel (0 = OFF, 1 = ON), for per-polarity maps.
inline int polarityIndex(const Event& e) { return e.polarity > 0 ? 1 : 0; }

/// A time-ordered run of events, as delivered by an EventReader. Reused between reads so that
/// streaming a file allocates nothing per packet once the capacity is reached.
struct EventPacket {
  std::vector<Event> events;
  /// Index of the first event of this packet within its stream (record number, 0-based).
  uint64_t first_index = 0;

  bool empty() const { return events.empty(); }
  std::size_t size() const { return events.size(); }
  int64_t frontTime() const { return events.front().t_ns; }
  int64_t backTime() const { return events.back().t_ns; }
};

}  // namespace asynevo
