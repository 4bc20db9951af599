#pragma once
// Reader of AsynEVO's binary .aevt event files (format: include/asynevo/io/event_file.hpp).

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/file_handle.hpp"
#include "event_checker.hpp"

namespace asynevo::io_detail {

class EventFileReader final : public EventReader {
 public:
  EventFileReader(const std::string& path, const ReaderOptions& options);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  StreamInfo info_;
  ReaderStats stats_;
  FileHandle file_;
  uint64_t count_ = 0;
  int packet_size_;
  EventChecker checker_;
  std::vector<unsigned char> bytes_;
  std::string error_;
};

}  // namespace asynevo::io_detail
