#pragma once
// iniVation AEDAT 4.0 (DV software; DVXplorer and DAVIS cameras): after the header (aedat4_header.hpp),
// packets of an 8-byte header (int32 stream id, int32 size) and a payload compressed as the IOHeader says,
// which decompresses to a size-prefixed FlatBuffer; an optional FileDataTable ends the file. Read here one
// packet at a time, so memory is bounded by the largest packet whatever the file size.
//
// Events come from the first stream whose typeIdentifier is EVTS (the lowest id); IMU (IMUS) and trigger
// (TRIG) packets are decompressed and their elements counted; frames (FRME), further event streams and
// other types are skipped unread and counted by packet. Sensor size: the event stream's sizeX/sizeY.
// Specification: https://docs.inivation.com/software/software-advanced-usage/file-formats/aedat-4.0.html
// What is read and what is not: docs/reference/formats_aedat4.md.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "aedat4_decompress.hpp"
#include "aedat4_header.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/file_handle.hpp"
#include "event_checker.hpp"

namespace asynevo::io_detail {

class Aedat4Reader final : public EventReader {
 public:
  Aedat4Reader(const std::string& path, const ReaderOptions& options);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  /// Reads packets until one of the event stream holds events; false at the end of the data.
  bool nextEventPacket();
  /// Decompresses (when the file is compressed) the payload just read into payload_; sets decoded_.
  void decode(uint32_t size);
  /// Verifies the decoded packet as a size-prefixed FlatBuffer of an elements vector and returns it (its
  /// length field, then the elements); nullptr when the packet has no vector.
  template <class Table>
  const uint8_t* elementsOf(const char* what);
  /// Positions the stream at the first packet with all counters cleared.
  void rewind();
  [[noreturn]] void fail(uint64_t offset, const std::string& message) const;
  std::string packetLabel() const;

  StreamInfo info_;
  ReaderStats stats_;
  ReaderOptions options_;
  FileHandle file_;
  aedat4::Header header_;
  std::unique_ptr<aedat4::Decompressor> decompressor_;  ///< null for uncompressed files
  int event_stream_ = -1;                               ///< id of the stream delivered
  uint64_t data_end_ = 0;        ///< the data table's offset, else the file size
  uint64_t next_offset_ = 0;     ///< offset of the next packet header
  uint64_t packet_offset_ = 0;   ///< offset of the current packet's header, for messages
  uint64_t packet_index_ = 0;    ///< index (0-based) of the current packet in the file
  uint64_t packets_seen_ = 0;
  int packet_stream_ = 0;
  std::vector<uint8_t> payload_;  ///< the packet as read from the file (never shrinks)
  std::vector<uint64_t> scratch_;  ///< an aligned copy of a packet when its writer aligned it differently
  const uint8_t* decoded_ = nullptr;
  std::size_t decoded_size_ = 0;
  const uint8_t* events_ = nullptr;  ///< the current event packet's Event structs
  std::size_t event_count_ = 0;
  std::size_t next_event_ = 0;
  EventChecker checker_{1, 1, 0};
  std::string error_;
};

}  // namespace asynevo::io_detail
