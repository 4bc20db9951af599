#pragma once
// MVSEC HDF5 events: dataset davis/left/events, N×4 doubles [x, y, t (s), p (±1)], DAVIS346 346×260.
// Read in hyperslab chunks of packet_size rows, so memory stays bounded.

#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "event_checker.hpp"
#include "hdf5_handle.hpp"

namespace asynevo::io_detail {

constexpr const char* kMvsecEventsPath = "davis/left/events";

class MvsecReader final : public EventReader {
 public:
  MvsecReader(const std::string& path, const ReaderOptions& options);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  StreamInfo info_;
  ReaderStats stats_;
  H5File file_;
  H5Dataset dataset_;
  uint64_t rows_ = 0;
  int packet_size_;
  EventChecker checker_;
  std::vector<double> rows_buffer_;
  std::string error_;
};

}  // namespace asynevo::io_detail
