#pragma once
// Writes small HDF5 files in exactly MVSEC's layout (no real MVSEC file is available to the tests):
// <seq>_data.hdf5: davis/left/events, N×4 float64 [x, y, t (s), p (±1)], chunked like the originals.

#include <hdf5.h>

#include <array>
#include <string>
#include <vector>

namespace asynevo::testing {

inline void writeMvsecEvents(const std::string& path, const std::vector<std::array<double, 4>>& rows,
                             const char* dataset_path = "davis/left/events") {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hsize_t dims[2] = {rows.size(), 4};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (!rows.empty()) {
    const hsize_t chunk[2] = {std::min<hsize_t>(rows.size(), 1000), 4};
    H5Pset_chunk(dcpl, 2, chunk);
  }
  const hid_t dataset = H5Dcreate2(file, dataset_path, H5T_IEEE_F64LE, space, lcpl, dcpl, H5P_DEFAULT);
  if (!rows.empty()) H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
  H5Dclose(dataset);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Pclose(lcpl);
  H5Fclose(file);
}

}  // namespace asynevo::testing

namespace asynevo::testing {

/// <seq>_gt.hdf5: davis/left/pose N×4×4 (row-major homogeneous T_w_c) and davis/left/pose_ts N.
inline void writeMvsecGroundTruth(const std::string& path, const std::vector<std::array<double, 16>>& poses,
                                  const std::vector<double>& times) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hsize_t pose_dims[3] = {poses.size(), 4, 4};
  const hsize_t time_dims[1] = {times.size()};
  const hid_t pose_space = H5Screate_simple(3, pose_dims, nullptr);
  const hid_t time_space = H5Screate_simple(1, time_dims, nullptr);
  const hid_t pose_set = H5Dcreate2(file, "davis/left/pose", H5T_IEEE_F64LE, pose_space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t time_set = H5Dcreate2(file, "davis/left/pose_ts", H5T_IEEE_F64LE, time_space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  if (!poses.empty()) H5Dwrite(pose_set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, poses.data());
  if (!times.empty()) H5Dwrite(time_set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, times.data());
  H5Dclose(pose_set);
  H5Dclose(time_set);
  H5Sclose(pose_space);
  H5Sclose(time_space);
  H5Pclose(lcpl);
  H5Fclose(file);
}

}  // namespace asynevo::testing
