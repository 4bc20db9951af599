#pragma once
// DSEC-style HDF5 events (format "dsec"; docs/reference/formats.md#dsec): one 1-D integer dataset per
// field, events/{x, y, t, p} with t in microseconds, an optional scalar t_offset (µs, added to t) and an
// optional ms_to_idx (ms → index of the first event at or after it), as DSEC and TUM-VIE write them; M3ED's
// prophesee/left/{x, y, t, p} is read too. The four fields are read in hyperslabs of packet_size values, so
// memory stays bounded whatever the file size. Compressed datasets (DSEC: Blosc + Zstd) need the HDF5
// filter plugin; a missing one is reported with the Debian package that provides it. With a rectification map
// (rectify_map.h5 beside the events, or ReaderOptions::rectify_map; io/dsec_rectify.hpp) the events are
// delivered in the rectified camera's pixels, and events mapped outside the sensor are dropped and counted.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "blosc_chunk_check.hpp"
#include "dsec_rectify.hpp"
#include "event_checker.hpp"
#include "hdf5_handle.hpp"

namespace asynevo::io_detail {

/// "dsec" when the HDF5 file at `path` holds DSEC-style (or M3ED) event datasets, else "mvsec" (the
/// MVSEC reader then names what is missing). For --format auto after the HDF5 signature.
std::string detectHdf5EventFormat(const std::string& path);

/// Throws InputError when a dataset's filter pipeline names a filter this HDF5 library cannot load (it would
/// only fail later, inside H5Dread, with a message that names no remedy); the message names the Debian package.
void h5CheckFiltersAvailable(const std::string& path, hid_t dataset, const std::string& name);

class DsecReader final : public EventReader {
 public:
  DsecReader(const std::string& path, const ReaderOptions& options);
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  void readSlabs(uint64_t n, EventPacket& packet);
  int64_t msIndexEntry(uint64_t ms);
  void checkMsIndex(uint64_t record, int64_t t_raw_us);
  void checkMsIndexEnd();

  StreamInfo info_;
  ReaderStats stats_;
  H5File file_;
  std::string group_;             // "events" or "prophesee/left"
  H5Dataset x_, y_, t_, p_;
  BloscChunkCheck chunk_checks_[4];  // of x, y, t, p
  H5Dataset ms_index_;            // ms_to_idx, when present
  uint64_t events_ = 0;           // values in each of x, y, t, p
  uint64_t records_ = 0;          // records read so far (delivered, or dropped by the rectification)
  std::optional<RectifyMap> rectify_;
  uint64_t ms_entries_ = 0;       // values in ms_to_idx
  uint64_t next_ms_ = 0;          // the next ms_to_idx entry to verify
  uint64_t ms_buffer_start_ = 0;  // ms of ms_buffer_[0]
  int64_t t_offset_us_ = 0;
  int packet_size_;
  EventChecker checker_;
  std::vector<int32_t> x_buffer_, y_buffer_, p_buffer_;
  std::vector<int64_t> t_buffer_, ms_buffer_;
  std::string error_;
};

}  // namespace asynevo::io_detail
