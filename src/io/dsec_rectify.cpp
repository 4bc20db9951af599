#include "dsec_rectify.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <system_error>

#include "asynevo/core/error.hpp"
#include "dsec_reader.hpp"
#include "hdf5_handle.hpp"
#include "hdf5_isolation.hpp"

namespace asynevo::io_detail {

namespace {

// A rectified coordinate's pixel, rounded to the nearest (halves away from zero, as std::lround), or -1 when
// that pixel is outside [0, size). Decided before rounding so that no huge value reaches std::lround.
long roundedInside(double v, int size) {
  if (!(v > -0.5 && v < static_cast<double>(size) - 0.5)) return -1;
  return std::lround(v);
}

}  // namespace

std::string rectifyMapBeside(const std::string& events_path) {
  const std::filesystem::path map = std::filesystem::path(events_path).parent_path() / kRectifyMapFile;
  std::error_code error;
  return std::filesystem::is_regular_file(map, error) ? map.string() : std::string();
}

RectifyMap::RectifyMap(const std::string& path, int width, int height, const std::string& size_origin)
    : width_(width) {
  // libhdf5 meets the file in a child process first (io/hdf5_isolation.hpp).
  if (!insideHdf5Child()) parseHdf5InChild(path, [&] { const RectifyMap probe(path, width, height, size_origin); });
  const H5QuietErrors quiet;
  const H5File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid())
    throw InputError(path,
                     "cannot open the rectification map as HDF5 (missing, unreadable or truncated file)");
  if (!h5PathExists(file.get(), kRectifyMapDataset)) {
    throw InputError(path,
                     fmt::format("missing dataset '{}': a DSEC rectification map holds one dataset '{}' of "
                                 "shape (height, width, 2)",
                                 kRectifyMapDataset, kRectifyMapDataset));
  }
  const H5Dataset dataset(H5Dopen2(file.get(), kRectifyMapDataset, H5P_DEFAULT));
  if (!dataset.valid())
    throw InputError(path, fmt::format("cannot open dataset '{}' (corrupt file?)", kRectifyMapDataset));
  const H5Space space(H5Dget_space(dataset.get()));
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
  hsize_t dims[H5S_MAX_RANK] = {};
  if (rank < 0 || rank > H5S_MAX_RANK || H5Sget_simple_extent_dims(space.get(), dims, nullptr) != rank)
    throw InputError(
        path, fmt::format("cannot read the shape of dataset '{}' (corrupt file?)", kRectifyMapDataset));
  if (rank != 3 || dims[0] != static_cast<hsize_t>(height) || dims[1] != static_cast<hsize_t>(width) ||
      dims[2] != 2) {
    throw InputError(
        path, fmt::format("dataset '{}' has shape ({}); the rectification map of the {}x{} sensor (size "
                          "from {}) has shape ({}, {}, 2): one (x, y) per raw pixel, indexed [y, x]",
                          kRectifyMapDataset, fmt::join(dims, dims + rank, ", "), width, height, size_origin,
                          height, width));
  }
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  h5CheckFloatDataset(path, dataset.get(), kRectifyMapDataset, 2 * pixels);
  h5CheckFiltersAvailable(path, dataset.get(), kRectifyMapDataset);
  std::vector<double> values(2 * pixels);
  if (H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    throw InputError(
        path, fmt::format("cannot read dataset '{}' (truncated or corrupt file?)", kRectifyMapDataset));

  target_.resize(pixels);
  for (uint64_t i = 0; i < pixels; ++i) {
    const double x = values[2 * i], y = values[2 * i + 1];
    if (!std::isfinite(x) || !std::isfinite(y)) {
      throw InputError(path,
                       fmt::format("dataset '{}' entry [{}, {}] (y, x) is ({:g}, {:g}): not a finite pixel "
                                   "position",
                                   kRectifyMapDataset, i / static_cast<uint64_t>(width),
                                   i % static_cast<uint64_t>(width), x, y));
    }
    const long xr = roundedInside(x, width), yr = roundedInside(y, height);
    if (xr < 0 || yr < 0) {
      target_[i] = kNoPixel;
      ++pixels_outside_;
    } else {
      target_[i] = static_cast<uint32_t>(yr) * static_cast<uint32_t>(width) + static_cast<uint32_t>(xr);
    }
  }
}

}  // namespace asynevo::io_detail
