#pragma once
// ECD ("IJRR 2017") text events: one event per line, `t x y p`, t in seconds, p in {0, 1}.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/file_handle.hpp"
#include "event_checker.hpp"

namespace asynevo::io_detail {

class EcdTextReader final : public EventReader {
 public:
  EcdTextReader(const std::string& path, const ReaderOptions& options);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  /// Moves the unparsed tail to the buffer's front and appends more of the file; false at end of file.
  bool refill();
  /// Parses one line [begin, end); returns false for blank/comment lines. Throws on bad lines.
  bool parseLine(const char* begin, const char* end, Event& event);
  [[noreturn]] void fail(const std::string& message) const;

  StreamInfo info_;
  ReaderStats stats_;
  FileHandle file_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;  ///< start of unparsed data in buffer_
  std::size_t end_ = 0;    ///< end of valid data in buffer_
  bool eof_ = false;
  uint64_t line_ = 0;      ///< 1-based number of the line being parsed
  int packet_size_;
  EventChecker checker_;
  std::string error_;      ///< scratch for checker messages
};

}  // namespace asynevo::io_detail
