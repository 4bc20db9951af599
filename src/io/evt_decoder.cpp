// EVT 3.0 and EVT 2.0 word decoding (see evt_decoder.hpp; the word layouts are listed in
// prophesee_reader.cpp above each reader).
#include "evt_decoder.hpp"

#include <fmt/format.h>

namespace asynevo::io_detail {

int64_t evtMicrosecondsToNs(uint64_t t_us, uint64_t offset, uint64_t wraps, const char* label) {
  constexpr uint64_t kMaxUs = static_cast<uint64_t>(INT64_MAX) / 1000;
  if (t_us > kMaxUs) {
    throw EvtDecodeError{offset, fmt::format("time {} µs after {} wraps of the {} time counter is out of range (more "
                                             "than {} µs; corrupt time words?)",
                                             t_us, wraps, label, kMaxUs)};
  }
  return static_cast<int64_t>(t_us) * 1000;
}

// ---------------------------------------------------------------------------------------------------
// EVT 3.0

void Evt3Decoder::reset() {
  wraps_ = time_high_ = time_low_ = 0;
  t_ns_ = 0;
  have_time_ = have_y_ = have_base_ = false;
  y_ = base_x_ = base_polarity_ = 0;
  vector_mask_ = 0;
  vector_x_ = 0;
  vector_offset_ = 0;
}

void Evt3Decoder::updateTime(uint64_t offset) {
  t_ns_ = evtMicrosecondsToNs((wraps_ << 24) | (time_high_ << 12) | time_low_, offset, wraps_, "EVT 3.0");
}

std::size_t Evt3Decoder::drainVector(Event* out, std::size_t n, std::size_t capacity, EventChecker& checker) {
  while (vector_mask_ != 0 && n < capacity) {
    const int bit = __builtin_ctz(vector_mask_);
    vector_mask_ &= vector_mask_ - 1;
    if (!checker.accept(t_ns_, vector_x_ + bit, y_, base_polarity_, out[n], error_))
      throw EvtDecodeError{vector_offset_, error_};
    ++n;
  }
  return n;
}

std::size_t Evt3Decoder::decode(const unsigned char* data, std::size_t& pos, std::size_t end, uint64_t base,
                                Event* out, std::size_t n, std::size_t capacity, EventChecker& checker,
                                ReaderStats& stats) {
  n = drainVector(out, n, capacity, checker);  // the rest of a vector the last packet could not hold
  while (n < capacity && pos < end) {
    const unsigned char* p = data + pos;
    const unsigned word = static_cast<unsigned>(p[0]) | (static_cast<unsigned>(p[1]) << 8);
    const uint64_t offset = base + pos;
    pos += 2;
    switch (word >> 12) {
      case 0x0:  // EVT_ADDR_Y
        y_ = static_cast<int>(word & 0x7FF);
        have_y_ = true;
        break;
      case 0x2:  // EVT_ADDR_X
        if (have_time_ && have_y_) {
          if (!checker.accept(t_ns_, word & 0x7FF, y_, (word >> 11) & 1, out[n], error_))
            throw EvtDecodeError{offset, error_};
          ++n;
        } else {
          ++stats.ignored_words;
        }
        break;
      case 0x3:  // VECT_BASE_X
        base_x_ = static_cast<int>(word & 0x7FF);
        base_polarity_ = static_cast<int>((word >> 11) & 1);
        have_base_ = true;
        break;
      case 0x4:    // VECT_12
      case 0x5: {  // VECT_8
        const bool twelve = (word >> 12) == 0x4;
        if (have_time_ && have_y_ && have_base_) {
          vector_mask_ = twelve ? (word & 0xFFF) : (word & 0xFF);
          vector_x_ = base_x_;
          vector_offset_ = offset;
          n = drainVector(out, n, capacity, checker);
        } else {
          ++stats.ignored_words;
        }
        base_x_ += twelve ? 12 : 8;
        break;
      }
      case 0x6:  // EVT_TIME_LOW
        time_low_ = word & 0xFFF;
        updateTime(offset);
        break;
      case 0x8: {  // EVT_TIME_HIGH
        const uint64_t high = word & 0xFFF;
        if (have_time_ && high < time_high_ && time_high_ - high >= 2048) ++wraps_;
        time_high_ = high;
        have_time_ = true;
        updateTime(offset);
        break;
      }
      case 0xA:  // EXT_TRIGGER
        ++stats.trigger_events;
        break;
      case 0x7:  // CONTINUED_4
      case 0xE:  // OTHERS
      case 0xF:  // CONTINUED_12
        ++stats.ignored_words;
        break;
      default:
        throw EvtDecodeError{offset, fmt::format("unknown EVT 3.0 word type {:04b} (word 0x{:04X}); types 0001, 1001, "
                                                 "1011, 1100 and 1101 are reserved (corrupt file, or not EVT 3.0?)",
                                                 word >> 12, word)};
    }
  }
  return n;
}

// ---------------------------------------------------------------------------------------------------
// EVT 2.0

void Evt2Decoder::reset() {
  wraps_ = time_high_ = base_us_ = 0;
  have_time_ = false;
}

std::size_t Evt2Decoder::decode(const unsigned char* data, std::size_t& pos, std::size_t end, uint64_t base,
                                Event* out, std::size_t n, std::size_t capacity, EventChecker& checker,
                                ReaderStats& stats) {
  while (n < capacity && pos < end) {
    const unsigned char* p = data + pos;
    const uint32_t word = static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
                          (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
    const uint64_t offset = base + pos;
    pos += 4;
    switch (word >> 28) {
      case 0x0:  // CD_OFF
      case 0x1:  // CD_ON
        if (have_time_) {
          const int64_t t_ns = evtMicrosecondsToNs(base_us_ + ((word >> 22) & 0x3F), offset, wraps_, "EVT 2.0");
          if (!checker.accept(t_ns, (word >> 11) & 0x7FF, word & 0x7FF, word >> 28, out[n], error_))
            throw EvtDecodeError{offset, error_};
          ++n;
        } else {
          ++stats.ignored_words;
        }
        break;
      case 0x8: {  // EVT_TIME_HIGH
        const uint64_t high = word & 0x0FFFFFFF;
        if (have_time_ && high < time_high_ && time_high_ - high >= (uint64_t{1} << 27)) ++wraps_;
        time_high_ = high;
        base_us_ = (wraps_ << 34) | (high << 6);
        evtMicrosecondsToNs(base_us_, offset, wraps_, "EVT 2.0");  // out of range here already: fail at the time word
        have_time_ = true;
        break;
      }
      case 0xA:  // EXT_TRIGGER
        ++stats.trigger_events;
        break;
      case 0xE:  // OTHERS
      case 0xF:  // CONTINUED
        ++stats.ignored_words;
        break;
      default:
        throw EvtDecodeError{offset, fmt::format("unknown EVT 2.0 word type {:04b} (word 0x{:08X}); only 0000, 0001, "
                                                 "1000, 1010, 1110 and 1111 are defined (corrupt file, or not EVT 2.0?)",
                                                 word >> 28, word)};
    }
  }
  return n;
}

}  // namespace asynevo::io_detail
