#pragma once
// libblosc 1.x bounds its reads of a compressed chunk by the sizes the chunk's own 16-byte Blosc header
// states (c-blosc's format, README_HEADER.rst: version, version of the codec, flags, type size, then
// nbytes, blocksize and cbytes, 32-bit little-endian). A corrupt header (cbytes of 0x76650030 for 48
// stored bytes, found 2026-11-27 by the dsec_events fuzz harness) makes it read far past the chunk inside
// H5Dread. BloscChunkCheck compares each chunk's header with the chunk as HDF5 stores it before the
// reader reads any value from that chunk.

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace asynevo::io_detail {

/// HDF5's registered filter id of Blosc.
inline constexpr H5Z_filter_t kBloscFilter = 32001;

class BloscChunkCheck {
 public:
  BloscChunkCheck() = default;
  /// Checks the chunks of the 1-D dataset `dataset` named `name` of the file at `path`, whose values are
  /// `value_bytes` bytes each in the file, when its last (outermost) filter is Blosc; does nothing otherwise.
  BloscChunkCheck(const std::string& path, hid_t dataset, std::string name, std::size_t value_bytes);

  /// Checks every chunk holding a value of [start, start + count) not checked before. Throws InputError
  /// naming the file, the dataset and the first value of the chunk when its Blosc header does not declare
  /// the chunk's size in values and the bytes it stores.
  void check(uint64_t start, uint64_t count);

 private:
  void checkChunk(uint64_t chunk);

  std::string path_, name_;
  hid_t dataset_ = -1;         // not owned
  uint64_t chunk_values_ = 0;  // 0: nothing to check
  std::size_t value_bytes_ = 0;
  uint64_t checked_below_ = 0;  // chunks [0, checked_below_) were checked (the readers read forward)
};

}  // namespace asynevo::io_detail
