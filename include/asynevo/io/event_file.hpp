#pragma once
// AsynEVO's binary event file (".aevt"): a fixed 64-byte header followed by fixed 16-byte records,
// little-endian. Parsing a 1 GB ECD text file takes seconds; reading its .aevt copy is a memcpy.
//
// Header: "ASYNEVOE" | u32 version (1) | u32 width | u32 height | u32 record bytes (16) |
//         u64 event count | i64 first t_ns | i64 last t_ns | 16 zero bytes
// Record: i64 t_ns | u16 x | u16 y | i8 polarity (+1/-1) | 3 zero bytes
// The format is documented in docs/formats.md.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "asynevo/core/event.hpp"
#include "asynevo/io/file_handle.hpp"

namespace asynevo {

constexpr char kEventFileMagic[8] = {'A', 'S', 'Y', 'N', 'E', 'V', 'O', 'E'};
constexpr std::size_t kEventFileHeaderBytes = 64;
constexpr std::size_t kEventFileRecordBytes = 16;

/// Writes an .aevt file. The header's count and time span are filled in by close() (also called by
/// the destructor, which cannot report errors: call close() yourself).
class EventFileWriter {
 public:
  EventFileWriter(const std::string& path, int width, int height);
  ~EventFileWriter();
  EventFileWriter(const EventFileWriter&) = delete;
  EventFileWriter& operator=(const EventFileWriter&) = delete;

  void write(const Event* events, std::size_t count);
  void write(const EventPacket& packet) { write(packet.events.data(), packet.events.size()); }
  /// Finalizes the header; throws InputError on an I/O failure.
  void close();

 private:
  void writeHeader();

  std::string path_;
  FileHandle file_;
  int width_, height_;
  uint64_t count_ = 0;
  int64_t first_t_ns_ = 0, last_t_ns_ = 0;
};

}  // namespace asynevo
