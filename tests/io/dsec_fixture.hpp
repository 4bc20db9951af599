#pragma once
// Writes small HDF5 files in the DSEC event layout, from its published description (no real DSEC file is
// available to the tests; https://dsec.ifi.uzh.ch/data-format/ and the DSEC scripts' EventSlicer):
//   events/x uint16, events/y uint16, events/p uint8 (0/1), events/t uint32 (µs, t_offset subtracted),
//   t_offset int64 scalar (µs), ms_to_idx uint64 (ms → index of the first event with t ≥ ms·1000),
// chunked, optionally with a compression filter (DSEC: Blosc with Zstd, HDF5 filter 32001).
// Variants: TUM-VIE (int64 t, no t_offset) and M3ED (group prophesee/left).
// DSEC's rectification map (rectify_map.h5): one dataset rectify_map of shape (height, width, 2), float32,
// indexed [y, x], holding the rectified [x, y] (the DSEC scripts' Sequence.rectify_events).

#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace asynevo::testing {

struct DsecEvents {
  std::vector<uint16_t> x, y;
  std::vector<int64_t> t;  // µs before t_offset, stored as `t_type`
  std::vector<uint8_t> p;
};

struct DsecLayout {
  std::string group = "events";
  hid_t t_type = H5T_STD_U32LE;        // DSEC: uint32; TUM-VIE, M3ED: int64
  bool write_t_offset = true;
  int64_t t_offset_us = 0;
  bool write_ms_to_idx = true;
  std::vector<uint64_t> ms_to_idx;     // empty: computed from t by DSEC's definition
  std::vector<std::string> skip;       // dataset names ("p", "t", ...) to leave out
  hsize_t chunk = 1000;
  H5Z_filter_t filter = H5Z_FILTER_NONE;  // e.g. 32001 (Blosc); cd_values below
  std::vector<unsigned> filter_values;
};

/// DSEC's ms_to_idx: entry ms is the number of events with t < ms·1000 (t sorted), up to the last event's ms.
inline std::vector<uint64_t> dsecMsToIdx(const std::vector<int64_t>& t) {
  std::vector<uint64_t> index;
  const int64_t last_ms = t.empty() ? 0 : t.back() / 1000;
  for (int64_t ms = 0; ms <= last_ms; ++ms)
    index.push_back(static_cast<uint64_t>(std::lower_bound(t.begin(), t.end(), ms * 1000) - t.begin()));
  return index;
}

inline void writeDsecColumn(hid_t file, hid_t lcpl, const std::string& name, hid_t file_type, hid_t memory_type,
                            const void* data, hsize_t n, const DsecLayout& layout) {
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (n > 0) {
    const hsize_t chunk = std::min(n, layout.chunk);
    H5Pset_chunk(dcpl, 1, &chunk);
    if (layout.filter != H5Z_FILTER_NONE) {
      H5Pset_filter(dcpl, layout.filter, H5Z_FLAG_MANDATORY, layout.filter_values.size(),
                    layout.filter_values.data());
    }
  }
  const hid_t dataset = H5Dcreate2(file, name.c_str(), file_type, space, lcpl, dcpl, H5P_DEFAULT);
  if (n > 0) H5Dwrite(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(dataset);
  H5Pclose(dcpl);
  H5Sclose(space);
}

inline void writeDsecEvents(const std::string& path, const DsecEvents& events, const DsecLayout& layout = {}) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  auto skipped = [&](const std::string& name) {
    return std::find(layout.skip.begin(), layout.skip.end(), name) != layout.skip.end();
  };
  const std::string g = layout.group + "/";
  if (!skipped("x"))
    writeDsecColumn(file, lcpl, g + "x", H5T_STD_U16LE, H5T_NATIVE_UINT16, events.x.data(), events.x.size(), layout);
  if (!skipped("y"))
    writeDsecColumn(file, lcpl, g + "y", H5T_STD_U16LE, H5T_NATIVE_UINT16, events.y.data(), events.y.size(), layout);
  if (!skipped("p"))
    writeDsecColumn(file, lcpl, g + "p", H5T_STD_U8LE, H5T_NATIVE_UINT8, events.p.data(), events.p.size(), layout);
  if (!skipped("t"))
    writeDsecColumn(file, lcpl, g + "t", layout.t_type, H5T_NATIVE_INT64, events.t.data(), events.t.size(), layout);
  if (layout.write_ms_to_idx) {
    const std::vector<uint64_t> index = layout.ms_to_idx.empty() ? dsecMsToIdx(events.t) : layout.ms_to_idx;
    DsecLayout plain = layout;
    plain.filter = H5Z_FILTER_NONE;
    writeDsecColumn(file, lcpl, "ms_to_idx", H5T_STD_U64LE, H5T_NATIVE_UINT64, index.data(), index.size(), plain);
  }
  if (layout.write_t_offset) {
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t offset = H5Dcreate2(file, "t_offset", H5T_STD_I64LE, scalar, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(offset, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &layout.t_offset_us);
    H5Dclose(offset);
    H5Sclose(scalar);
  }
  H5Pclose(lcpl);
  H5Fclose(file);
}

/// A rectify_map.h5 with `values` (row-major over `dims`) in dataset `name`, stored as `type`.
inline void writeRectifyMap(const std::string& path, const std::vector<float>& values,
                            const std::vector<hsize_t>& dims, const std::string& name = "rectify_map",
                            hid_t type = H5T_IEEE_F32LE) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t dataset = H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(dataset, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(dataset);
  H5Sclose(space);
  H5Fclose(file);
}

/// The map of a `width` x `height` sensor that sends raw pixel (x, y) to `f(x, y)` = {x', y'}.
template <typename F>
std::vector<float> rectifyMapValues(int width, int height, F f) {
  std::vector<float> values;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::pair<float, float> target = f(x, y);
      values.push_back(target.first);
      values.push_back(target.second);
    }
  }
  return values;
}

/// `n` events at 1 event per 7 µs from t = 3 µs, pixels inside 640x480, polarity alternating in runs.
inline DsecEvents syntheticDsecEvents(int n) {
  DsecEvents e;
  for (int i = 0; i < n; ++i) {
    e.x.push_back(static_cast<uint16_t>((i * 13) % 640));
    e.y.push_back(static_cast<uint16_t>((i * 7) % 480));
    e.t.push_back(3 + 7 * static_cast<int64_t>(i));
    e.p.push_back(static_cast<uint8_t>((i / 3) % 2));
  }
  return e;
}

}  // namespace asynevo::testing
