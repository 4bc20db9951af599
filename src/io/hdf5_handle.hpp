#pragma once
// Small RAII wrappers for the HDF5 C API and the checks every HDF5 reader makes before it reads a value.

#include <hdf5.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include "asynevo/core/error.hpp"
#include "hdf5_layout.hpp"

namespace asynevo::io_detail {

/// Owns one hid_t and closes it with the matching H5?close.
template <herr_t (*Close)(hid_t)>
class H5Handle {
 public:
  H5Handle() = default;
  explicit H5Handle(hid_t id) : id_(id) {}
  ~H5Handle() {
    if (id_ >= 0) Close(id_);
  }
  H5Handle(H5Handle&& other) noexcept : id_(std::exchange(other.id_, -1)) {}
  H5Handle& operator=(H5Handle&& other) noexcept {
    std::swap(id_, other.id_);
    return *this;
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
};

using H5File = H5Handle<H5Fclose>;
using H5Dataset = H5Handle<H5Dclose>;
using H5Space = H5Handle<H5Sclose>;
using H5Type = H5Handle<H5Tclose>;
using H5PropertyList = H5Handle<H5Pclose>;

/// Silences HDF5's automatic error-stack printing while alive (errors are reported by our exceptions).
class H5QuietErrors {
 public:
  H5QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &old_func_, &old_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~H5QuietErrors() { H5Eset_auto2(H5E_DEFAULT, old_func_, old_data_); }
  H5QuietErrors(const H5QuietErrors&) = delete;
  H5QuietErrors& operator=(const H5QuietErrors&) = delete;

 private:
  H5E_auto2_t old_func_ = nullptr;
  void* old_data_ = nullptr;
};

/// True when the (possibly nested, "a/b/c") link exists in the file.
inline bool h5PathExists(hid_t file, const std::string& path) {
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

/// The storage half of h5CheckFloatDataset, for values of any type of `size` bytes (`size` > 0): the chunk
/// layout's value size (hdf5_layout.hpp) and the stored bytes against the declared values.
inline void h5CheckStoredSize(const std::string& path, hid_t dataset, const char* name, uint64_t elements,
                              std::size_t size) {
  h5CheckChunkValueSize(path, dataset, name, size);
  std::error_code error;
  const std::uintmax_t file_bytes = std::filesystem::file_size(path, error);
  const H5PropertyList create(H5Dget_create_plist(dataset));
  const bool filtered = !create.valid() || H5Pget_nfilters(create.get()) != 0;
  const bool too_many = elements > std::numeric_limits<uint64_t>::max() / size;
  if (!error && (too_many || (!filtered && elements * size > file_bytes))) {
    throw InputError(path, fmt::format("dataset '{}' declares {} values of {} bytes, more than the {}-byte file "
                                       "holds (corrupt file?)",
                                       name, elements, size, file_bytes));
  }
  // Without filters the stored bytes are the values themselves. Fewer stored than declared is a corrupt
  // chunk index or layout message: libhdf5 1.10 then copies a whole chunk out of a smaller buffer (a
  // heap overflow inside H5Dread, found 2026-11-26 by the mvsec_events fuzz harness).
  const hsize_t stored = H5Dget_storage_size(dataset);
  if (!filtered && elements * size > stored) {
    throw InputError(path, fmt::format("dataset '{}' declares {} values of {} bytes ({} bytes) but stores {} bytes "
                                       "(corrupt chunk index or layout?)",
                                       name, elements, size, elements * size, stored));
  }
  // Without filters every allocated chunk is stored whole: a chunk larger than the stored bytes, or stored
  // bytes that are no whole number of chunks, is a corrupt layout message that libhdf5 1.10 follows out of
  // its buffer (a second heap overflow in H5Dread the harness found, chunk 40x65 on a 40x4 dataset).
  if (!filtered && create.valid() && H5Pget_layout(create.get()) == H5D_CHUNKED && elements > 0) {
    hsize_t chunk[H5S_MAX_RANK] = {};
    const int rank = H5Pget_chunk(create.get(), H5S_MAX_RANK, chunk);
    uint64_t chunk_bytes = size;
    for (int i = 0; i < rank && chunk_bytes <= stored; ++i) chunk_bytes *= chunk[i];
    if (rank <= 0 || chunk_bytes == 0 || chunk_bytes > stored || stored % chunk_bytes != 0) {
      throw InputError(path, fmt::format("dataset '{}' stores {} bytes, not a whole number of its chunks ({} "
                                         "values of {} bytes each; corrupt chunk index or layout?)",
                                         name, stored, rank > 0 ? fmt::format("{}", fmt::join(chunk, chunk + rank, "x"))
                                                                : std::string("no chunk size"),
                                         size));
    }
  }
}

/// Checks, before anything is read or allocated, that the dataset `name` of the file at `path` holds
/// `elements` 32- or 64-bit floating-point numbers that the file can hold: without compression filters
/// the raw bytes must fit in the file. Throws InputError otherwise. A corrupt file can declare a float
/// type of 4 GB per value, or billions of values with no storage behind them (read as fill values):
/// HDF5 would allocate the conversion buffer, the reader the values, or loop over them for ever (found
/// 2026-11-26 by the mvsec_groundtruth fuzz harness).
inline void h5CheckFloatDataset(const std::string& path, hid_t dataset, const char* name, uint64_t elements) {
  const H5Type type(H5Dget_type(dataset));
  const std::size_t size = type.valid() ? H5Tget_size(type.get()) : 0;
  if (!type.valid() || H5Tget_class(type.get()) != H5T_FLOAT || (size != 4 && size != 8)) {
    throw InputError(path, fmt::format("dataset '{}' does not hold 32- or 64-bit floating-point numbers (its values "
                                       "are {} bytes each; corrupt file?)",
                                       name, size));
  }
  h5CheckStoredSize(path, dataset, name, elements, size);
}

}  // namespace asynevo::io_detail
