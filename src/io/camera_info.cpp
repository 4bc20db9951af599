#include "asynevo/io/camera_info.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "asynevo/core/error.hpp"

namespace asynevo {

CameraModel cameraFromCameraInfo(const CameraInfoFields& info) {
  if (info.width == 0 || info.height == 0 || info.width > 65535 || info.height > 65535)
    throw Error(fmt::format("the camera info states a {}x{} image", info.width, info.height));
  if (info.k[0] == 0.0)
    throw Error("the camera is uncalibrated (K[0] is 0, ROS's mark of an uncalibrated camera)");
  std::vector<double> d = info.d;
  DistortionModel distortion = DistortionModel::kNone;
  bool all_zero = true;
  for (double x : d) all_zero = all_zero && x == 0.0;
  if (d.empty() || all_zero) {
    d.clear();
  } else if (info.distortion_model == "plumb_bob") {
    if (d.size() != 5 && d.size() != 4)
      throw Error(
          fmt::format("distortion model plumb_bob with {} coefficients (k1 k2 p1 p2 k3: 5)", d.size()));
    distortion = DistortionModel::kRadtan;
  } else if (info.distortion_model == "equidistant") {
    if (d.size() != 4)
      throw Error(fmt::format("distortion model equidistant with {} coefficients (k1..k4: 4)", d.size()));
    distortion = DistortionModel::kEquidistant;
  } else {
    throw Error("distortion model '" + info.distortion_model +
                "' is not read by AsynEVO (plumb_bob, equidistant)");
  }
  try {
    return CameraModel(static_cast<int>(info.width), static_cast<int>(info.height), info.k[0], info.k[4],
                       info.k[2], info.k[5], distortion, d);
  } catch (const std::invalid_argument& e) {
    throw Error(e.what());
  }
}

}  // namespace asynevo
