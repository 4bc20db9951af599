#pragma once
// The sensor size of a stream that states none: the bounding box of its events from pixel (0, 0), found by
// reading the stream once to its end (in packets, so in bounded memory). Used by the readers of formats
// whose header may lack a size (Prophesee RAW and DAT, AEDAT 4.0).

#include <algorithm>
#include <utility>

#include "asynevo/io/event_reader.hpp"

namespace asynevo::io_detail {

/// {largest x + 1, largest y + 1} over all events `reader` delivers; {1, 1} when it delivers none.
inline std::pair<int, int> extentOfEvents(EventReader& reader) {
  EventPacket packet;
  int max_x = 0;
  int max_y = 0;
  while (reader.read(packet)) {
    for (const Event& e : packet.events) {
      max_x = std::max<int>(max_x, e.x);
      max_y = std::max<int>(max_y, e.y);
    }
  }
  return {max_x + 1, max_y + 1};
}

}  // namespace asynevo::io_detail
