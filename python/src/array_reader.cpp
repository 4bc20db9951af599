#include "array_reader.hpp"

#include <algorithm>
#include <utility>

namespace asynevo::python {

ArrayReader::ArrayReader(std::vector<Event> events, int width, int height, int packet_size)
    : events_(std::move(events)), packet_size_(static_cast<std::size_t>(std::max(1, packet_size))) {
  info_.path = "<arrays>";
  info_.format = "arrays";
  info_.width = width;
  info_.height = height;
  info_.size_origin = "the arrays' sensor size";
}

bool ArrayReader::read(EventPacket& packet) {
  packet.events.clear();
  packet.first_index = next_;
  const std::size_t n = std::min(packet_size_, events_.size() - next_);
  const auto first = events_.begin() + static_cast<std::ptrdiff_t>(next_);
  packet.events.assign(first, first + static_cast<std::ptrdiff_t>(n));
  next_ += n;
  stats_.events += n;
  return n > 0;
}

}  // namespace asynevo::python
