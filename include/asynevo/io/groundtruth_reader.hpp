#pragma once
// Ground truth of a dataset, whatever its format: ECD/TUM text (groundtruth.txt) or MVSEC HDF5
// (<seq>_gt.hdf5: davis/left/pose N×4×4 homogeneous T_w_c, davis/left/pose_ts N seconds).

#include <string>

#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/io/trajectory_io.hpp"

namespace asynevo {

/// Reads MVSEC ground truth. Every pose must be finite with an orthonormal rotation (|RᵀR − I| < 1e-3,
/// det > 0; re-orthonormalized to unit quaternions) and the times non-decreasing; otherwise InputError
/// names the file and the record.
StampedTrajectory readMvsecGroundTruth(const std::string& path);

/// Reads ground truth from an HDF5 (MVSEC) or text (ECD/TUM) file, detected from the content.
StampedTrajectory readGroundTruth(const std::string& path, TrajectoryReadReport* report = nullptr);

}  // namespace asynevo
