#pragma once
// One event-file format through the streaming reader, packet by packet, checking every accepted event.

#include <limits>

#include "asynevo/io/event_reader.hpp"
#include "fuzz_input.hpp"

namespace asynevo::fuzz {

/// `width`, `height`: the sensor size to pass, for formats whose files state none and have no default (dsec).
inline int fuzzEventReader(const uint8_t* data, std::size_t size, const char* format, const char* suffix,
                           int width = 0, int height = 0) {
  const InputFile input(data, size, suffix);
  rejectCleanly([&] {
    ReaderOptions options;
    options.format = format;
    options.width = width;
    options.height = height;
    options.packet_size = 256;  // many packets: exercise the readers' chunk boundaries
    options.rectify_map = "none";  // the input alone, whatever rectify_map.h5 lies in the temp folder
    auto reader = openEventReader(input.path(), options);
    const StreamInfo& info = reader->info();
    require(info.width > 0 && info.height > 0, "a reader accepted a stream without a sensor size");
    EventPacket packet;
    int64_t last = std::numeric_limits<int64_t>::min();
    while (reader->read(packet)) {
      require(!packet.empty(), "read() returned true with an empty packet");
      requireValidEvents(packet, info.width, info.height, last);
    }
    require(packet.empty(), "read() returned false with events in the packet");
  });
  return 0;
}

}  // namespace asynevo::fuzz
