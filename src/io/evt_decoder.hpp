#pragma once
// Stateful decoders of Prophesee's EVT 3.0 and EVT 2.0 word streams, over byte buffers handed in one
// after another. The Prophesee RAW readers (prophesee_reader.cpp) feed them a file's chunks; the ROS bag
// reader (rosbag_reader.cpp) feeds them the payloads of event_camera_msgs/EventPacket messages, so the
// decoding state (time base, row, vector base, time wraps) carries across messages as it does across
// chunks. Bit layouts: prophesee_reader.cpp, from Prophesee's public "EVT 3.0 Format" and "EVT 2.0
// Format" pages.

#include <cstddef>
#include <cstdint>
#include <string>

#include "asynevo/core/event.hpp"
#include "asynevo/io/event_reader.hpp"
#include "event_checker.hpp"

namespace asynevo::io_detail {

/// A bad word or event at `offset` (in the caller's coordinates: each decode call is given the offset
/// of its buffer's first byte). Callers turn it into an InputError that names their file.
struct EvtDecodeError {
  uint64_t offset = 0;
  std::string message;
};

/// EVT 3.0: 16-bit little-endian words.
class Evt3Decoder {
 public:
  /// Forgets all state, as at the start of a stream.
  void reset();
  /// Delivers first what is left of a vector word a full packet could not take, then decodes the words
  /// of data[pos, end) (whole words: end - pos even) into out[n, capacity). Returns the new n and moves
  /// pos past the words used; stops early only when out is full. `base` is the offset of data[0].
  /// Events are checked by `checker`; skipped words and triggers are counted in `stats`. Throws
  /// EvtDecodeError.
  std::size_t decode(const unsigned char* data, std::size_t& pos, std::size_t end, uint64_t base, Event* out,
                     std::size_t n, std::size_t capacity, EventChecker& checker, ReaderStats& stats);
  /// Whether events of a vector word are still waiting for room in a packet.
  bool pending() const { return vector_mask_ != 0; }
  uint64_t wraps() const { return wraps_; }

 private:
  std::size_t drainVector(Event* out, std::size_t n, std::size_t capacity, EventChecker& checker);
  void updateTime(uint64_t offset);

  uint64_t wraps_ = 0;          ///< times the 24-bit time base wrapped around
  uint64_t time_high_ = 0;
  uint64_t time_low_ = 0;
  int64_t t_ns_ = 0;
  bool have_time_ = false;      ///< a TIME_HIGH was seen
  bool have_y_ = false;         ///< an ADDR_Y was seen
  bool have_base_ = false;      ///< a VECT_BASE_X was seen
  int y_ = 0;
  int base_x_ = 0;
  int base_polarity_ = 0;
  uint32_t vector_mask_ = 0;    ///< events of the current vector word not yet delivered
  int vector_x_ = 0;            ///< x of the vector word's bit 0
  uint64_t vector_offset_ = 0;  ///< offset of the vector word, for messages
  std::string error_;
};

/// EVT 2.0: 32-bit little-endian words.
class Evt2Decoder {
 public:
  void reset();
  /// As Evt3Decoder::decode, for whole 32-bit words (end - pos a multiple of 4).
  std::size_t decode(const unsigned char* data, std::size_t& pos, std::size_t end, uint64_t base, Event* out,
                     std::size_t n, std::size_t capacity, EventChecker& checker, ReaderStats& stats);
  bool pending() const { return false; }
  uint64_t wraps() const { return wraps_; }

 private:
  uint64_t wraps_ = 0;          ///< times the 34-bit time wrapped around
  uint64_t time_high_ = 0;
  uint64_t base_us_ = 0;        ///< (wraps << 34) + (time_high << 6)
  bool have_time_ = false;
  std::string error_;
};

/// A decoded time in µs as ns; throws EvtDecodeError naming `offset` when it does not fit in int64 ns
/// (time wraps counted without end in a corrupt or crafted stream). `label` is "EVT 3.0" or "EVT 2.0".
int64_t evtMicrosecondsToNs(uint64_t t_us, uint64_t offset, uint64_t wraps, const char* label);

}  // namespace asynevo::io_detail
