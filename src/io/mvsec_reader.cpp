#include "mvsec_reader.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::io_detail {

namespace {
constexpr int kMvsecWidth = 346;  // DAVIS346
constexpr int kMvsecHeight = 260;
}  // namespace

MvsecReader::MvsecReader(const std::string& path, const ReaderOptions& options)
    : packet_size_(options.packet_size),
      checker_(1, 1, 0) {
  info_.path = path;
  info_.format = "mvsec";
  info_.width = options.width > 0 ? options.width : kMvsecWidth;
  info_.height = options.height > 0 ? options.height : kMvsecHeight;
  // The MVSEC file stores no size either (its sensor is a DAVIS346).
  info_.size_origin = options.width > 0 || options.height > 0 ? options.size_origin : "the MVSEC default, a DAVIS346";
  checker_ = EventChecker(info_.width, info_.height, options.max_time_reversal_ns, info_.size_origin, true);
  const H5QuietErrors quiet;
  file_ = H5File(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file_.valid()) throw InputError(path, "cannot open as HDF5 (missing, unreadable or truncated file)");
  if (!h5PathExists(file_.get(), kMvsecEventsPath))
    throw InputError(path, std::string("no dataset '") + kMvsecEventsPath + "' (not an MVSEC *_data.hdf5 file?)");
  dataset_ = H5Dataset(H5Dopen2(file_.get(), kMvsecEventsPath, H5P_DEFAULT));
  if (!dataset_.valid()) throw InputError(path, std::string("cannot open dataset '") + kMvsecEventsPath + "'");
  const H5Space space(H5Dget_space(dataset_.get()));
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2 || H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2 ||
      dims[1] != 4) {
    throw InputError(path, std::string("dataset '") + kMvsecEventsPath + "' must be N×4 [x, y, t, p]");
  }
  if (dims[0] > std::numeric_limits<uint64_t>::max() / 4)
    throw InputError(path, std::string("dataset '") + kMvsecEventsPath + "' has more values than 64 bits count");
  h5CheckFloatDataset(path, dataset_.get(), kMvsecEventsPath, dims[0] * 4);
  rows_ = dims[0];
}

bool MvsecReader::read(EventPacket& packet) {
  packet.events.clear();
  packet.first_index = stats_.events;
  const uint64_t n = std::min<uint64_t>(rows_ - stats_.events, static_cast<uint64_t>(packet_size_));
  if (n == 0) return false;
  rows_buffer_.resize(n * 4);
  {
    const H5QuietErrors quiet;
    const H5Space file_space(H5Dget_space(dataset_.get()));
    const hsize_t start[2] = {stats_.events, 0};
    const hsize_t count[2] = {n, 4};
    const H5Space memory_space(H5Screate_simple(2, count, nullptr));
    if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
        H5Dread(dataset_.get(), H5T_NATIVE_DOUBLE, memory_space.get(), file_space.get(), H5P_DEFAULT,
                rows_buffer_.data()) < 0) {
      throw InputError::atRecord(info_.path, stats_.events, "cannot read events (truncated or corrupt file)");
    }
  }
  packet.events.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    const double* row = &rows_buffer_[i * 4];
    const uint64_t record = stats_.events + i;
    for (int k = 0; k < 4; ++k) {
      if (!std::isfinite(row[k])) throw InputError::atRecord(info_.path, record, "non-finite value (NaN or inf)");
    }
    if (row[0] != std::floor(row[0]) || row[1] != std::floor(row[1]) || row[3] != std::floor(row[3]))
      throw InputError::atRecord(info_.path, record, "x, y and p must be whole numbers");
    if (std::fabs(row[2]) > 9.0e9) throw InputError::atRecord(info_.path, record, "time out of range");
    if (std::fabs(row[0]) > 1e6 || std::fabs(row[1]) > 1e6 || std::fabs(row[3]) > 1e6)
      throw InputError::atRecord(info_.path, record, "x, y or p far out of range (wrong column order?)");
    if (!checker_.accept(secondsToNs(row[2]), static_cast<int64_t>(row[0]), static_cast<int64_t>(row[1]),
                         static_cast<int64_t>(row[3]), packet.events[i], error_)) {
      throw InputError::atRecord(info_.path, record, error_);
    }
  }
  stats_.events += n;
  stats_.clamped_times = checker_.clamped();
  return true;
}

}  // namespace asynevo::io_detail
