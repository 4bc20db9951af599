#include "blosc_chunk_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "asynevo/core/error.hpp"
#include "hdf5_handle.hpp"
#include "little_endian.hpp"

namespace asynevo::io_detail {

namespace {

constexpr std::size_t kBloscHeaderBytes = 16;

}  // namespace

BloscChunkCheck::BloscChunkCheck(const std::string& path, hid_t dataset, std::string name,
                                 std::size_t value_bytes)
    : path_(path), name_(std::move(name)), dataset_(dataset), value_bytes_(value_bytes) {
  const H5PropertyList create(H5Dget_create_plist(dataset));
  if (!create.valid() || H5Pget_layout(create.get()) != H5D_CHUNKED) return;
  const int filters = H5Pget_nfilters(create.get());
  unsigned flags = 0;
  std::size_t values = 0;
  if (filters <= 0 || H5Pget_filter2(create.get(), static_cast<unsigned>(filters - 1), &flags, &values,
                                     nullptr, 0, nullptr, nullptr) != kBloscFilter) {
    return;
  }
  hsize_t chunk[1] = {0};
  if (H5Pget_chunk(create.get(), 1, chunk) == 1) chunk_values_ = chunk[0];
}

void BloscChunkCheck::check(uint64_t start, uint64_t count) {
  if (chunk_values_ == 0 || count == 0) return;
  const uint64_t last = (start + count - 1) / chunk_values_;
  for (uint64_t chunk = std::max(checked_below_, start / chunk_values_); chunk <= last; ++chunk)
    checkChunk(chunk);
  checked_below_ = std::max(checked_below_, last + 1);
}

void BloscChunkCheck::checkChunk(uint64_t chunk) {
  const uint64_t first_value = chunk * chunk_values_;
  const hsize_t offset[1] = {first_value};
  unsigned filter_mask = 0;
  haddr_t address = 0;
  hsize_t stored = 0;
  const H5QuietErrors quiet;
  if (H5Dget_chunk_info_by_coord(dataset_, offset, &filter_mask, &address, &stored) < 0)
    throw InputError::atRecord(path_, first_value,
                               fmt::format("dataset '{}': cannot locate its chunk", name_));
  if (filter_mask != 0) return;  // stored without the filter
  // H5Dread and H5Dread_chunk find a chunk by libhdf5's chunk lookup (H5Dget_chunk_storage_size); in a
  // corrupt index that can differ from the size the index lists (H5Dget_chunk_info_by_coord). A chunk the
  // index lists as absent (fill values) but the lookup finds would be decompressed unchecked, and a read
  // by the listed size would run past its buffer: the two must agree.
  hsize_t read_size = 0;
  if (H5Dget_chunk_storage_size(dataset_, offset, &read_size) < 0 || read_size != stored) {
    throw InputError::atRecord(path_, first_value,
                               fmt::format("dataset '{}': its chunk index lists {} bytes for the chunk, "
                                           "the chunk lookup {} (corrupt chunk index?)",
                                           name_, stored, read_size));
  }
  if (stored == 0) return;  // not allocated: fill values
  const uint64_t values_bytes = chunk_values_ * value_bytes_;
  // Blosc stores at most its header more than the values (BLOSC_MAX_OVERHEAD, 16 bytes).
  if (stored < kBloscHeaderBytes || stored > values_bytes + kBloscHeaderBytes) {
    throw InputError::atRecord(path_, first_value,
                               fmt::format("dataset '{}': a Blosc chunk of {} bytes for {} bytes of values "
                                           "(corrupt chunk?)",
                                           name_, stored, values_bytes));
  }
  std::vector<uint8_t> bytes(stored);
  uint32_t filters = 0;
  if (H5Dread_chunk(dataset_, H5P_DEFAULT, offset, &filters, bytes.data()) < 0)
    throw InputError::atRecord(path_, first_value, fmt::format("dataset '{}': cannot read its chunk", name_));
  const uint32_t nbytes = load32(&bytes[4]), cbytes = load32(&bytes[12]);
  if (cbytes != stored || nbytes != values_bytes) {
    throw InputError::atRecord(
        path_, first_value,
        fmt::format("dataset '{}': the chunk's Blosc header declares {} bytes compressed "
                    "into {}, but the chunk holds {} bytes of values and stores {} "
                    "(corrupt chunk?)",
                    name_, nbytes, cbytes, values_bytes, stored));
  }
}

}  // namespace asynevo::io_detail
