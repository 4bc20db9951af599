#include "asynevo/io/groundtruth_reader.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/file_handle.hpp"
#include "hdf5_handle.hpp"
#include "hdf5_isolation.hpp"

namespace asynevo {

namespace {

using io_detail::H5Dataset;
using io_detail::H5File;
using io_detail::H5QuietErrors;
using io_detail::H5Space;

constexpr const char* kPosePath = "davis/left/pose";
constexpr const char* kPoseTimePath = "davis/left/pose_ts";

// Reads a whole float64 dataset and its dimensions.
std::vector<double> readDoubles(const std::string& file_path, hid_t file, const char* dataset_path,
                                std::vector<hsize_t>& dims) {
  if (!io_detail::h5PathExists(file, dataset_path))
    throw InputError(file_path, std::string("no dataset '") + dataset_path + "' (not an MVSEC *_gt.hdf5 file?)");
  const H5Dataset dataset(H5Dopen2(file, dataset_path, H5P_DEFAULT));
  const H5Space space(H5Dget_space(dataset.get()));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank <= 0) throw InputError(file_path, std::string("dataset '") + dataset_path + "' is empty or scalar");
  dims.assign(static_cast<std::size_t>(rank), 0);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t d : dims) {
    if (d != 0 && total > std::numeric_limits<hsize_t>::max() / d)
      throw InputError(file_path, std::string("dataset '") + dataset_path + "' has more values than 64 bits count");
    total *= d;
  }
  io_detail::h5CheckFloatDataset(file_path, dataset.get(), dataset_path, total);
  std::vector<double> values(total);
  if (total > 0 && H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    throw InputError(file_path, std::string("cannot read dataset '") + dataset_path + "' (corrupt file?)");
  return values;
}

}  // namespace

StampedTrajectory readMvsecGroundTruth(const std::string& path) {
  // libhdf5 meets the file in a child process first (io/hdf5_isolation.hpp).
  if (!io_detail::insideHdf5Child()) io_detail::parseHdf5InChild(path, [&] { readMvsecGroundTruth(path); });
  const H5QuietErrors quiet;
  const H5File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.valid()) throw InputError(path, "cannot open as HDF5 (missing, unreadable or truncated file)");
  std::vector<hsize_t> pose_dims, time_dims;
  const std::vector<double> poses = readDoubles(path, file.get(), kPosePath, pose_dims);
  const std::vector<double> times = readDoubles(path, file.get(), kPoseTimePath, time_dims);
  if (pose_dims.size() != 3 || pose_dims[1] != 4 || pose_dims[2] != 4)
    throw InputError(path, std::string("dataset '") + kPosePath + "' must be N×4×4");
  if (time_dims.size() != 1 || time_dims[0] != pose_dims[0])
    throw InputError(path, std::string("dataset '") + kPoseTimePath + "' must hold one time per pose");
  if (pose_dims[0] == 0) throw InputError(path, "the ground truth holds no poses");
  StampedTrajectory trajectory;
  trajectory.reserve(pose_dims[0]);
  for (hsize_t i = 0; i < pose_dims[0]; ++i) {
    const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> T(&poses[i * 16]);
    if (!T.allFinite() || !std::isfinite(times[i]))
      throw InputError::atRecord(path, i, "non-finite pose or time (NaN or inf)");
    // The MVSEC event reader's bound: int64 nanoseconds hold ±9.2e9 s; beyond, the conversion is undefined.
    if (std::fabs(times[i]) > 9.0e9)
      throw InputError::atRecord(path, i, fmt::format("time {} s is out of range (|t| > 9e9 s)", times[i]));
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 || R.determinant() <= 0)
      throw InputError::atRecord(path, i, "the rotation block is not a rotation matrix");
    StampedPose pose;
    pose.t_ns = secondsToNs(times[i]);
    pose.p_w_c = T.topRightCorner<3, 1>();
    pose.q_w_c = Eigen::Quaterniond(R).normalized();
    if (!trajectory.empty() && pose.t_ns < trajectory.back().t_ns)
      throw InputError::atRecord(path, i, "time goes backwards; poses must be sorted by time");
    trajectory.push_back(pose);
  }
  return trajectory;
}

StampedTrajectory readGroundTruth(const std::string& path, TrajectoryReadReport* report) {
  if (io_detail::hasHdf5Signature(path)) return readMvsecGroundTruth(path);
  return readTumTrajectory(path, report);
}

}  // namespace asynevo
