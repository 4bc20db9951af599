#pragma once
// A calibration parser: an accepted camera has a size and finite, positive focal lengths.

#include <cmath>

#include "asynevo/core/camera/camera_model.hpp"
#include "fuzz_input.hpp"

namespace asynevo::fuzz {

inline void requireValidCamera(const CameraModel& camera) {
  require(camera.width() > 0 && camera.height() > 0, "an accepted camera has no size");
  require(std::isfinite(camera.fx()) && std::isfinite(camera.fy()) && camera.fx() > 0 && camera.fy() > 0,
          "an accepted camera has a focal length that is not finite and positive");
  require(std::isfinite(camera.cx()) && std::isfinite(camera.cy()), "an accepted principal point is not finite");
}

}  // namespace asynevo::fuzz
