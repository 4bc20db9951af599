#pragma once
// A camera model from the fields of a ROS sensor_msgs/CameraInfo message, shared by the bag reader
// (io/rosbag_topics.hpp: the first CameraInfo message of a bag) and the ROS node (apps/asynevo_ros: a live
// camera_info topic). The rules are documented in docs/reference/formats_rosbag.md#calibration.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"

namespace asynevo {

/// The CameraInfo fields a camera model is made of.
struct CameraInfoFields {
  uint32_t width = 0, height = 0;
  std::string distortion_model;  ///< "plumb_bob" (k1 k2 p1 p2 [k3]) or "equidistant" (k1..k4)
  std::vector<double> d;         ///< D
  std::array<double, 9> k{};     ///< K, row-major: fx 0 cx; 0 fy cy; 0 0 1
};

/// The camera model: pinhole from K, radtan for plumb_bob, equidistant for equidistant, none when D is empty
/// or all zero. Throws Error with a sentence (no location: the caller adds it) for a size of 0 or above
/// 65535, an uncalibrated camera (K[0] = 0), another distortion model or a wrong number of coefficients.
CameraModel cameraFromCameraInfo(const CameraInfoFields& info);

}  // namespace asynevo
