#pragma once
// Prophesee event files: RAW recordings in the EVT 3.0 and EVT 2.0 encodings, and DAT files of decoded
// CD events. Each is an ASCII header of "% keyword value" lines followed by binary little-endian data,
// read here in fixed-size chunks (memory bounded by the chunk and the packet, whatever the file size).
//
// Written from Prophesee's public format documentation, nothing else:
//   "RAW File Format"  https://docs.prophesee.ai/stable/data/file_formats/raw.html
//   "EVT 3.0 Format"   https://docs.prophesee.ai/stable/data/encoding_formats/evt3.html
//   "EVT 2.0 Format"   https://docs.prophesee.ai/stable/data/encoding_formats/evt2.html
//   "DAT File Format"  https://docs.prophesee.ai/stable/data/file_formats/dat.html
// What is read, what is skipped and how the sensor size is found: docs/reference/formats_prophesee.md.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/file_handle.hpp"
#include "event_checker.hpp"
#include "evt_decoder.hpp"

namespace asynevo::io_detail {

/// One "% keyword value" line of a Prophesee header.
struct PropheseeHeaderLine {
  uint64_t offset = 0;  ///< byte offset of the line's '%'
  std::string text;     ///< the line without the leading "% " and the line end
  std::string keyword;  ///< text up to the first space
  std::string value;    ///< text after the first space
};

/// A Prophesee RAW or DAT header: the "% ..." lines at the start of the file.
struct PropheseeHeader {
  std::vector<PropheseeHeaderLine> lines;
  uint64_t data_offset = 0;  ///< first byte after the header (0 when the file has none)

  /// The first line with this keyword (ASCII case-insensitive), or nullptr.
  const PropheseeHeaderLine* find(const std::string& keyword) const;
};

/// Reads the header at the start of `file` (any position; the function seeks to 0). A header line is
/// "% " followed by text and a line feed; the header ends at the first line that is not one (or whose
/// bytes are control characters, i.e. binary data that happens to start with "% "), or after "% end".
/// Throws InputError when the file ends inside a header line or the header exceeds 1 MiB.
PropheseeHeader readPropheseeHeader(std::FILE* file, const std::string& path);

/// The format a header names: "evt3", "evt2" or "dat"; "" when it names none. Throws InputError for
/// encodings it names that no reader here decodes (EVT 2.1, event-frame formats).
std::string propheseeFormatFromHeader(const PropheseeHeader& header, const std::string& path);

/// Common part of the three readers: the header, the sensor size, chunked reading of whole words and
/// the per-event checks. Derived classes decode words.
class PropheseeReader : public EventReader {
 public:
  bool read(EventPacket& packet) final;
  const StreamInfo& info() const final { return info_; }
  const ReaderStats& stats() const final { return stats_; }

 protected:
  /// Opens `path`, reads its header and checks it does not name another format than `format`.
  PropheseeReader(const std::string& path, const ReaderOptions& options, const char* format, int word_bytes);

  /// Decodes up to `capacity` events into `out`; returns how many (0 only at the end of the data).
  virtual std::size_t decode(Event* out, std::size_t capacity) = 0;
  /// Forgets all decoding state (time base, row, vector base), as at the start of the data.
  virtual void resetDecoder() = 0;

  /// Settles the sensor size (header, else the configured size, else a known camera, else the events'
  /// bounding box from one extra pass) and positions the stream at the first data word. Derived
  /// constructors call it last. `limit` is the largest size the format's coordinate fields can hold.
  void startData(uint64_t data_offset, int limit);

  /// Makes at least one whole word available at pos_; false at the end of the data. Throws InputError
  /// when the file ends inside a word.
  bool nextChunk();
  /// Byte offset in the file of the chunk position `pos`.
  uint64_t offsetOf(std::size_t pos) const { return chunk_offset_ + pos; }
  [[noreturn]] void fail(uint64_t offset, const std::string& message) const;
  /// A decoded time in µs as ns; throws InputError naming `offset` when it does not fit in int64 ns
  /// (time wraps counted without end in a corrupt or crafted file).
  int64_t usToNs(uint64_t t_us, uint64_t offset) const {
    constexpr uint64_t kMaxUs = static_cast<uint64_t>(INT64_MAX) / 1000;
    if (t_us > kMaxUs) {
      fail(offset, fmt::format("time {} µs after {} wraps of the {} time counter is out of range (more than "
                               "{} µs; corrupt time words?)",
                               t_us, wrapsSoFar(), format_label_, kMaxUs));
    }
    return static_cast<int64_t>(t_us) * 1000;
  }
  /// Times the format's time counter has wrapped so far (for messages).
  virtual uint64_t wrapsSoFar() const = 0;
  /// Checks and stores one event at out[n]; throws InputError naming `offset` when it is invalid.
  void emit(Event& out, int64_t t_ns, int64_t x, int64_t y, int64_t polarity, uint64_t offset) {
    if (!checker_.accept(t_ns, x, y, polarity, out, error_)) fail(offset, error_);
  }

  StreamInfo info_;
  ReaderStats stats_;
  ReaderOptions options_;
  PropheseeHeader header_;
  FileHandle file_;
  std::vector<unsigned char> chunk_;
  std::size_t pos_ = 0;         ///< next unread byte in chunk_
  std::size_t end_ = 0;         ///< end of the whole words in chunk_
  std::size_t filled_ = 0;      ///< end of the valid bytes in chunk_ (a partial word may follow end_)
  uint64_t chunk_offset_ = 0;   ///< file offset of chunk_[0]
  uint64_t data_offset_ = 0;    ///< file offset of the first data word
  bool eof_ = false;
  int word_bytes_;
  EventChecker checker_{1, 1, 0};
  std::string error_;
  std::string format_label_;    ///< "EVT 3.0", "EVT 2.0", "DAT" for messages
};

/// Prophesee RAW, EVT 3.0: 16-bit words, a 24-bit µs time base split into TIME_HIGH and TIME_LOW,
/// rows set by ADDR_Y, single events (ADDR_X) and vectors of up to 12 events (VECT_BASE_X, VECT_12,
/// VECT_8).
class Evt3Reader final : public PropheseeReader {
 public:
  Evt3Reader(const std::string& path, const ReaderOptions& options);

 private:
  std::size_t decode(Event* out, std::size_t capacity) override;
  void resetDecoder() override { decoder_.reset(); }
  uint64_t wrapsSoFar() const override { return decoder_.wraps(); }

  Evt3Decoder decoder_;
};

/// Prophesee RAW, EVT 2.0: 32-bit words; CD_OFF/CD_ON carry x, y and the 6 low time bits, TIME_HIGH
/// the 28 high bits of a 34-bit µs time.
class Evt2Reader final : public PropheseeReader {
 public:
  Evt2Reader(const std::string& path, const ReaderOptions& options);

 private:
  std::size_t decode(Event* out, std::size_t capacity) override;
  void resetDecoder() override { decoder_.reset(); }
  uint64_t wrapsSoFar() const override { return decoder_.wraps(); }

  Evt2Decoder decoder_;
};

/// Prophesee DAT: after the header, an event-type byte and an event-size byte (8), then 8-byte
/// records: a 32-bit µs time and a 32-bit word with x (bits 0-13), y (14-27) and polarity (28-31).
class DatReader final : public PropheseeReader {
 public:
  DatReader(const std::string& path, const ReaderOptions& options);

 private:
  std::size_t decode(Event* out, std::size_t capacity) override;
  void resetDecoder() override;
  uint64_t wrapsSoFar() const override { return wraps_; }

  uint64_t wraps_ = 0;          ///< times the 32-bit µs time wrapped around
  uint32_t last_raw_t_ = 0;
  bool have_time_ = false;
};

}  // namespace asynevo::io_detail
