#pragma once
// An EventReader over events already in memory (arrays handed in from Python), so they go through the
// same pipeline as a file.

#include <vector>

#include "asynevo/io/event_reader.hpp"

namespace asynevo::python {

class ArrayReader final : public EventReader {
 public:
  ArrayReader(std::vector<Event> events, int width, int height, int packet_size = 65536);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  std::vector<Event> events_;
  std::size_t next_ = 0;
  std::size_t packet_size_;
  StreamInfo info_;
  ReaderStats stats_;
};

}  // namespace asynevo::python
