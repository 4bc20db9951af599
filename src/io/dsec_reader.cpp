#include "dsec_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "asynevo/core/error.hpp"
#include "asynevo/io/sensor_size.hpp"

namespace asynevo::io_detail {

namespace {

// The groups that hold the x, y, t, p datasets: DSEC and TUM-VIE, then M3ED's left event camera.
constexpr const char* kEventGroups[] = {"events", "prophesee/left"};

// |t| in µs up to which t·1000 ns fits in int64 (about 292 years).
constexpr int64_t kMaxTimeUs = std::numeric_limits<int64_t>::max() / 1000;

// Where to get the HDF5 filter plugin for a filter id (Debian 12 package names).
std::string filterPluginAdvice(H5Z_filter_t id) {
  switch (id) {
    case 32001:  // Blosc (DSEC: Blosc with its Zstd codec)
      return "install the Debian package hdf5-filter-plugin-blosc-serial (sudo apt-get install "
             "hdf5-filter-plugin-blosc-serial)";
    case 307:    // BZip2
    case 32004:  // LZ4
      return "install the Debian package hdf5-filter-plugin (sudo apt-get install hdf5-filter-plugin)";
    case 32013:  // ZFP
      return "install the Debian package hdf5-filter-plugin-zfp-serial";
    default:
      return "install an HDF5 filter plugin for it (Debian: hdf5-filter-plugin, hdf5-filter-plugin-blosc-serial; "
             "or the plugins of the hdf5plugin Python package) and set HDF5_PLUGIN_PATH to its folder";
  }
}

// A compressed dataset's stored size says nothing about its length (h5CheckStoredSize checks only unfiltered
// ones), so a corrupt length of 10^12 with no chunks behind it would read as 10^12 fill-value events (all
// t = 0, x = y = 0: valid) for hours. A file written whole has every chunk: require them all.
void checkChunksAllocated(const std::string& path, hid_t dataset, const std::string& name, uint64_t length) {
  const H5PropertyList create(H5Dget_create_plist(dataset));
  if (!create.valid() || H5Pget_layout(create.get()) != H5D_CHUNKED || length == 0) return;
  hsize_t chunk[1] = {0};
  if (H5Pget_chunk(create.get(), 1, chunk) != 1 || chunk[0] == 0)
    throw InputError(path, fmt::format("dataset '{}' has no valid chunk size (corrupt file?)", name));
  // HDF5 creates no chunk larger than a fixed-size dataset. A corrupt layout message can declare one: a
  // compressed chunk then decompresses to fewer bytes than libhdf5 1.10 copies out of it (a heap over-read
  // in H5Dread, found 2026-11-27 by the dsec_events fuzz harness, on a packet after the first).
  const H5Space space(H5Dget_space(dataset));  // libhdf5 1.10 counts nothing with H5S_ALL
  hsize_t max_length[1] = {0};
  if (!space.valid() || H5Sget_simple_extent_dims(space.get(), nullptr, max_length) != 1 ||
      (max_length[0] != H5S_UNLIMITED && chunk[0] > max_length[0])) {
    throw InputError(path, fmt::format("dataset '{}' declares chunks of {} values, more than its fixed size of {} "
                                       "values (corrupt layout?)",
                                       name, chunk[0], max_length[0]));
  }
  const uint64_t expected = length / chunk[0] + (length % chunk[0] != 0 ? 1 : 0);
  hsize_t stored = 0;
  if (H5Dget_num_chunks(dataset, space.get(), &stored) < 0 || stored < expected) {
    throw InputError(path, fmt::format("dataset '{}' declares {} values in {} chunks of {} but stores {} chunks "
                                       "(truncated or corrupt file?)",
                                       name, length, expected, chunk[0], stored));
  }
}

// libhdf5 keeps 1 MB of decompressed chunks per dataset. A chunk larger than that is decompressed again for
// every packet that reads part of it (Blosc+Zstd chunks of 4 MB: 11.5 instead of 72 M events/s): reopen the
// dataset with a cache that holds two chunks, up to 64 MB (measured by bench/io/dsec_reader_bench.cpp).
H5Dataset withChunkCache(hid_t file, const std::string& name, H5Dataset dataset, std::size_t value_bytes) {
  constexpr uint64_t kDefaultCacheBytes = 1 << 20;
  constexpr uint64_t kMaxCacheBytes = 64 << 20;
  const H5PropertyList create(H5Dget_create_plist(dataset.get()));
  hsize_t chunk[1] = {0};
  if (!create.valid() || H5Pget_layout(create.get()) != H5D_CHUNKED || H5Pget_chunk(create.get(), 1, chunk) != 1)
    return dataset;
  const uint64_t chunk_bytes = chunk[0] * value_bytes;
  if (chunk_bytes <= kDefaultCacheBytes / 2 || chunk_bytes > kMaxCacheBytes / 2) return dataset;
  const H5PropertyList access(H5Pcreate(H5P_DATASET_ACCESS));
  if (!access.valid() || H5Pset_chunk_cache(access.get(), 521, 2 * chunk_bytes, H5D_CHUNK_CACHE_W0_DEFAULT) < 0)
    return dataset;
  dataset = H5Dataset();  // closed first: while it is open, libhdf5 hands out the same object, with its cache
  H5Dataset reopened(H5Dopen2(file, name.c_str(), access.get()));
  return reopened.valid() ? std::move(reopened) : H5Dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
}

// Opens a 1-D integer dataset and returns it with its length, after the type, storage and filter checks.
H5Dataset openIntegerColumn(const std::string& path, hid_t file, const std::string& name, uint64_t& length) {
  if (!h5PathExists(file, name)) throw InputError(path, fmt::format("missing dataset '{}'", name));
  H5Dataset dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
  if (!dataset.valid()) throw InputError(path, fmt::format("cannot open dataset '{}' (corrupt file?)", name));
  const H5Space space(H5Dget_space(dataset.get()));
  hsize_t dims[1] = {0};
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
      H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 1) {
    throw InputError(path, fmt::format("dataset '{}' must be one-dimensional (one value per event)", name));
  }
  const H5Type type(H5Dget_type(dataset.get()));
  const std::size_t size = type.valid() ? H5Tget_size(type.get()) : 0;
  if (!type.valid() || H5Tget_class(type.get()) != H5T_INTEGER || (size != 1 && size != 2 && size != 4 && size != 8)) {
    throw InputError(path, fmt::format("dataset '{}' does not hold integers of 1, 2, 4 or 8 bytes (DSEC: x, y "
                                       "uint16, p uint8, t uint32 microseconds)",
                                       name));
  }
  h5CheckStoredSize(path, dataset.get(), name.c_str(), dims[0], size);
  h5CheckFiltersAvailable(path, dataset.get(), name);
  checkChunksAllocated(path, dataset.get(), name, dims[0]);
  length = dims[0];
  return withChunkCache(file, name, std::move(dataset), size);
}

// Reads `count` values from `start` of a 1-D dataset, converted to `memory_type`, into `out`.
bool readSlab(hid_t dataset, hid_t memory_type, uint64_t start, uint64_t count, void* out) {
  const H5Space file_space(H5Dget_space(dataset));
  const hsize_t offset[1] = {start};
  const hsize_t size[1] = {count};
  const H5Space memory_space(H5Screate_simple(1, size, nullptr));
  return file_space.valid() && memory_space.valid() &&
         H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, offset, nullptr, size, nullptr) >= 0 &&
         H5Dread(dataset, memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, out) >= 0;
}

}  // namespace

void h5CheckFiltersAvailable(const std::string& path, hid_t dataset, const std::string& name) {
  const H5PropertyList create(H5Dget_create_plist(dataset));
  if (!create.valid()) throw InputError(path, fmt::format("cannot read the storage properties of dataset '{}'", name));
  const int filters = H5Pget_nfilters(create.get());
  for (int i = 0; i < filters; ++i) {
    unsigned flags = 0;
    std::size_t values = 0;
    char filter_name[64] = {};
    const H5Z_filter_t id =
        H5Pget_filter2(create.get(), static_cast<unsigned>(i), &flags, &values, nullptr, sizeof(filter_name),
                       filter_name, nullptr);
    if (id < 0) throw InputError(path, fmt::format("cannot read the filter pipeline of dataset '{}'", name));
    if ((flags & H5Z_FLAG_OPTIONAL) != 0 || H5Zfilter_avail(id) > 0) continue;
    throw InputError(path, fmt::format("dataset '{}' is compressed with HDF5 filter {} ('{}'), which this HDF5 "
                                       "library cannot load: {}",
                                       name, id, filter_name, filterPluginAdvice(id)));
  }
}

std::string detectHdf5EventFormat(const std::string& path) {
  const H5QuietErrors quiet;
  const H5File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid()) return "mvsec";  // the MVSEC reader reports the unreadable file
  if (h5PathExists(file.get(), "davis/left/events")) return "mvsec";
  for (const char* group : kEventGroups) {
    if (h5PathExists(file.get(), std::string(group) + "/x")) return "dsec";
  }
  return "mvsec";
}

DsecReader::DsecReader(const std::string& path, const ReaderOptions& options)
    : packet_size_(options.packet_size), checker_(1, 1, 0) {
  info_.path = path;
  info_.format = "dsec";
  const H5QuietErrors quiet;
  file_ = H5File(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file_.valid()) throw InputError(path, "cannot open as HDF5 (missing, unreadable or truncated file)");
  for (const char* group : kEventGroups) {
    if (h5PathExists(file_.get(), std::string(group) + "/x")) {
      group_ = group;
      break;
    }
  }
  if (group_.empty()) {
    throw InputError(path, "no dataset 'events/x' (nor M3ED's 'prophesee/left/x'): not a DSEC-style HDF5 event file");
  }
  // The file states no sensor size, and the largest x and y seen are not one: ask for it.
  if (options.width <= 0 || options.height <= 0) {
    throw InputError(path, fmt::format("DSEC-style HDF5 files store no sensor size; {} (DSEC: 640x480; TUM-VIE "
                                       "and M3ED: 1280x720)",
                                       kSensorSizeHowTo));
  }
  info_.width = options.width;
  info_.height = options.height;
  info_.size_origin = options.size_origin;
  checker_ = EventChecker(info_.width, info_.height, options.max_time_reversal_ns, info_.size_origin, true);

  const std::string prefix = group_ + "/";
  uint64_t lengths[4] = {};
  x_ = openIntegerColumn(path, file_.get(), prefix + "x", lengths[0]);
  y_ = openIntegerColumn(path, file_.get(), prefix + "y", lengths[1]);
  t_ = openIntegerColumn(path, file_.get(), prefix + "t", lengths[2]);
  p_ = openIntegerColumn(path, file_.get(), prefix + "p", lengths[3]);
  const char* names[4] = {"x", "y", "t", "p"};
  for (int i = 1; i < 4; ++i) {
    if (lengths[i] != lengths[0]) {
      throw InputError(path, fmt::format("datasets '{}x' ({} values) and '{}{}' ({} values) differ in length: "
                                         "every event needs all four fields (truncated or corrupt file?)",
                                         prefix, lengths[0], prefix, names[i], lengths[i]));
    }
  }
  events_ = lengths[0];
  const hid_t columns[4] = {x_.get(), y_.get(), t_.get(), p_.get()};
  for (int i = 0; i < 4; ++i) {
    const H5Type type(H5Dget_type(columns[i]));
    chunk_checks_[i] = BloscChunkCheck(path, columns[i], prefix + names[i], H5Tget_size(type.get()));
  }

  if (group_ == "events" && h5PathExists(file_.get(), "t_offset")) {
    const H5Dataset offset(H5Dopen2(file_.get(), "t_offset", H5P_DEFAULT));
    const H5Space space(offset.valid() ? H5Dget_space(offset.get()) : -1);
    const H5Type type(offset.valid() ? H5Dget_type(offset.get()) : -1);
    if (!space.valid() || !type.valid() || H5Tget_class(type.get()) != H5T_INTEGER || H5Tget_size(type.get()) > 8 ||
        H5Sget_simple_extent_npoints(space.get()) != 1) {
      throw InputError(path, "dataset 't_offset' must be a single integer (microseconds added to events/t)");
    }
    if (H5Dread(offset.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &t_offset_us_) < 0)
      throw InputError(path, "cannot read dataset 't_offset' (corrupt file?)");
    if (t_offset_us_ > kMaxTimeUs || t_offset_us_ < -kMaxTimeUs)
      throw InputError(path, fmt::format("t_offset {} µs is out of range", t_offset_us_));
  }
  if (group_ == "events" && h5PathExists(file_.get(), "ms_to_idx"))
    ms_index_ = openIntegerColumn(path, file_.get(), "ms_to_idx", ms_entries_);

  // DSEC's rectify_map.h5: named, found beside the events, or turned off with "none".
  const std::string map = options.rectify_map.empty() ? rectifyMapBeside(path) : options.rectify_map;
  if (!map.empty() && map != "none") {
    rectify_.emplace(map, info_.width, info_.height, info_.size_origin);
    info_.rectify_map = map;
  }
}

int64_t DsecReader::msIndexEntry(uint64_t ms) {
  if (ms < ms_buffer_start_ || ms >= ms_buffer_start_ + ms_buffer_.size()) {
    const uint64_t n = std::min<uint64_t>(ms_entries_ - ms, static_cast<uint64_t>(packet_size_));
    ms_buffer_.resize(n);
    const H5QuietErrors quiet;
    if (!readSlab(ms_index_.get(), H5T_NATIVE_INT64, ms, n, ms_buffer_.data()))
      throw InputError(info_.path, fmt::format("cannot read ms_to_idx[{}] (truncated or corrupt file)", ms));
    ms_buffer_start_ = ms;
  }
  return ms_buffer_[ms - ms_buffer_start_];
}

// ms_to_idx[ms] must be the index of the first event whose t (before t_offset) is at least ms·1000 µs, the
// number of events before that time. Called for each event in order: every entry whose time the event
// reaches is due now.
void DsecReader::checkMsIndex(uint64_t record, int64_t t_raw_us) {
  while (next_ms_ < ms_entries_ && t_raw_us >= 0 && next_ms_ * 1000 <= static_cast<uint64_t>(t_raw_us)) {
    const int64_t entry = msIndexEntry(next_ms_);
    if (entry < 0 || static_cast<uint64_t>(entry) != record) {
      throw InputError::atRecord(info_.path, record,
                                 fmt::format("ms_to_idx[{}] is {}, but the first event at or after {} ms (t before "
                                             "t_offset) is this one: the index does not match the events "
                                             "(corrupt file?)",
                                             next_ms_, entry, next_ms_));
    }
    ++next_ms_;
  }
}

// Entries past the last event's time point one past the last event.
void DsecReader::checkMsIndexEnd() {
  for (; next_ms_ < ms_entries_; ++next_ms_) {
    const int64_t entry = msIndexEntry(next_ms_);
    if (entry < 0 || static_cast<uint64_t>(entry) != events_) {
      throw InputError(info_.path, fmt::format("ms_to_idx[{}] is {}, but no event is at or after {} ms: it must "
                                               "be the event count {} (corrupt file?)",
                                               next_ms_, entry, next_ms_, events_));
    }
  }
}

bool DsecReader::read(EventPacket& packet) {
  packet.events.clear();
  packet.first_index = stats_.events;
  // With a rectification map a slab may lose every event: read on until one is delivered or the file ends.
  while (packet.events.empty()) {
    const uint64_t n = std::min<uint64_t>(events_ - records_, static_cast<uint64_t>(packet_size_));
    if (n == 0) {
      if (ms_index_.valid()) checkMsIndexEnd();
      return false;
    }
    readSlabs(n, packet);
  }
  return true;
}

// Reads records [records_, records_ + n) into `packet`, replacing its events with those they deliver (all
// of them, or without the ones a rectification map sends outside the sensor).
void DsecReader::readSlabs(uint64_t n, EventPacket& packet) {
  x_buffer_.resize(n);
  y_buffer_.resize(n);
  p_buffer_.resize(n);
  t_buffer_.resize(n);
  {
    const H5QuietErrors quiet;
    const uint64_t start = records_;
    for (BloscChunkCheck& check : chunk_checks_) check.check(start, n);
    if (!readSlab(x_.get(), H5T_NATIVE_INT32, start, n, x_buffer_.data()) ||
        !readSlab(y_.get(), H5T_NATIVE_INT32, start, n, y_buffer_.data()) ||
        !readSlab(t_.get(), H5T_NATIVE_INT64, start, n, t_buffer_.data()) ||
        !readSlab(p_.get(), H5T_NATIVE_INT32, start, n, p_buffer_.data())) {
      throw InputError::atRecord(info_.path, start, "cannot read events (truncated or corrupt file)");
    }
  }
  packet.events.resize(n);
  std::size_t kept = 0;
  const bool check_index = ms_index_.valid();
  for (uint64_t i = 0; i < n; ++i) {
    const uint64_t record = records_ + i;
    const int64_t t_raw = t_buffer_[i];
    int64_t t_us = 0;
    if (__builtin_add_overflow(t_raw, t_offset_us_, &t_us) || t_us > kMaxTimeUs || t_us < -kMaxTimeUs) {
      throw InputError::atRecord(info_.path, record,
                                 fmt::format("time {} µs (+ t_offset {} µs) is out of range", t_raw, t_offset_us_));
    }
    Event& event = packet.events[kept];
    if (!checker_.accept(t_us * 1000, x_buffer_[i], y_buffer_[i], p_buffer_[i], event, error_))
      throw InputError::atRecord(info_.path, record, error_);
    if (check_index) checkMsIndex(record, t_raw);
    if (rectify_ && !rectify_->map(event.x, event.y, event.x, event.y)) {
      ++stats_.rectified_outside;
      continue;
    }
    ++kept;
  }
  packet.events.resize(kept);
  records_ += n;
  stats_.events += kept;
  stats_.clamped_times = checker_.clamped();
}

}  // namespace asynevo::io_detail
