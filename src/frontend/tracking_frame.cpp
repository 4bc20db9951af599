// Tracking frame: raw binned pixels or the rectified pinhole image (include/asynevo/frontend/
// tracking_frame.hpp). Binned pixel xb covers sensor pixels [xb b, xb b + b), centre u = (xb + 0.5) b - 0.5.
#include "asynevo/frontend/tracking_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace asynevo::frontend {

TrackingFrame::TrackingFrame(int width, int height, int bin_shift, UndistortionTable<float> undistortion)
    : width_(width),
      height_(height),
      bin_shift_(bin_shift),
      undistortion_(std::move(undistortion)),
      grid_width_(width),
      grid_height_(height) {}

TrackingFrame::TrackingFrame(const CameraModel& camera, int bin_shift)
    : width_((camera.width() + (1 << bin_shift) - 1) >> bin_shift),
      height_((camera.height() + (1 << bin_shift) - 1) >> bin_shift),
      bin_shift_(bin_shift),
      rectified_(true),
      camera_(camera) {
  const double b = static_cast<double>(1 << bin_shift);
  f_x_ = camera.fx() / b;
  f_y_ = camera.fy() / b;
  c_x_ = (camera.cx() + 0.5) / b - 0.5;
  c_y_ = (camera.cy() + 0.5) / b - 0.5;
  positions_.assign(2 * static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_),
                    std::numeric_limits<float>::quiet_NaN());
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const Eigen::Vector2d pixel((x + 0.5) * b - 0.5, (y + 0.5) * b - 0.5);
      const UndistortResult u = camera.undistort(camera.pixelToDistorted(pixel));
      if (!u.converged) {
        ++without_position_;
        continue;
      }
      const double fx = f_x_ * u.xn.x() + c_x_, fy = f_y_ * u.xn.y() + c_y_;
      const std::size_t i = 2 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + x);
      positions_[i] = static_cast<float>(fx);
      positions_[i + 1] = static_cast<float>(fy);
      min_x = std::min(min_x, fx);
      min_y = std::min(min_y, fy);
      max_x = std::max(max_x, fx);
      max_y = std::max(max_y, fy);
    }
  }
  if (!(min_x <= max_x)) {  // no pixel has a position: an empty grid of one cell
    grid_width_ = grid_height_ = 1;
    return;
  }
  // One cell of slack on each side: rounding a position near the edge stays inside the grid.
  origin_x_ = static_cast<float>(std::floor(min_x) - 1.0);
  origin_y_ = static_cast<float>(std::floor(min_y) - 1.0);
  grid_width_ = static_cast<int>(std::ceil(max_x - origin_x_)) + 2;
  grid_height_ = static_cast<int>(std::ceil(max_y - origin_y_)) + 2;
}

bool TrackingFrame::inside(float x, float y, float margin) const {
  if (!rectified_) return withinMargin(x, y, width_, height_, margin);
  // Back through the distortion to the sensor pixel, then to binned pixels.
  const Eigen::Vector2d u = camera_->normalizedToPixel(normalized(x, y));
  const double b = static_cast<double>(1 << bin_shift_);
  return withinMargin((u.x() + 0.5) / b - 0.5, (u.y() + 0.5) / b - 0.5, width_, height_, double(margin));
}

bool TrackingFrame::measurement(float x, float y, float& sensor_x, float& sensor_y, float& xn, float& yn) const {
  if (rectified_) {
    const Eigen::Vector2d n = normalized(x, y);
    const Eigen::Vector2d u = camera_->normalizedToPixel(n);
    sensor_x = static_cast<float>(u.x());
    sensor_y = static_cast<float>(u.y());
    xn = static_cast<float>(n.x());
    yn = static_cast<float>(n.y());
    return std::isfinite(sensor_x) && std::isfinite(sensor_y);
  }
  if (bin_shift_ > 0) {  // back to sensor pixels: binned pixel centre (x + 0.5) b - 0.5
    const float b = static_cast<float>(1 << bin_shift_);
    x = (x + 0.5f) * b - 0.5f;
    y = (y + 0.5f) * b - 0.5f;
  }
  sensor_x = x;
  sensor_y = y;
  if (undistortion_.width() == 0) {
    xn = x;
    yn = y;
    return true;
  }
  return undistortion_.interpolate(x, y, xn, yn);
}

}  // namespace asynevo::frontend
