#pragma once
// Writes events as ECD text ("events.txt"): one line "t x y p" per event, t in seconds with exactly 9
// decimals (the nanosecond, so the ECD reader gives back the same int64 t_ns), p 1 (ON) or 0 (OFF).
// Hand-rolled formatting: the file can hold hundreds of millions of events.

#include <cstdint>
#include <cstdio>
#include <string>

#include "asynevo/core/event.hpp"

namespace asynevo {

class EventTextWriter {
 public:
  /// Throws Error when the file cannot be created.
  explicit EventTextWriter(const std::string& path);
  ~EventTextWriter();
  EventTextWriter(const EventTextWriter&) = delete;
  EventTextWriter& operator=(const EventTextWriter&) = delete;

  void write(const Event& e);
  void write(const EventPacket& packet) {
    for (const Event& e : packet.events) write(e);
  }
  /// Flushes and closes the file; throws Error on an I/O failure.
  void close();

 private:
  void flush();

  std::string path_;
  std::FILE* file_;
  std::string buffer_;
};

}  // namespace asynevo
