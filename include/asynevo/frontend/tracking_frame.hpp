#pragma once
// The image coordinates the HASTE trackers work in (docs/method/frontend.md, "Tracking frame").
//
// Raw: the frontend's (binned) sensor pixels, as the events arrive. A lens's distortion then warps a
// patch as it crosses the image (a DAVIS240C's barrel distortion shrinks it by up to 40 % radially
// towards the corners), and a rigid template follows the warp with an error that grows with the
// track's age.
// Rectified: the pinhole image with the camera's own intrinsics, x = K_b undistort(pixel centre), with
// K_b the intrinsics scaled to the binned pixels. A plane's patch moving parallel to it keeps its shape
// there wherever it is in the image. Events keep their pixel's position (a table); the frame extends
// beyond the sensor's rectangle where the distortion is barrel-shaped.

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/camera/undistortion_table.hpp"

namespace asynevo::frontend {

class TrackingFrame {
 public:
  /// The binned pixels themselves (`width` x `height` binned pixels of 2^bin_shift sensor pixels);
  /// `undistortion` (sensor size; empty = identity, xn = x) gives a measurement's normalized coordinates.
  TrackingFrame(int width, int height, int bin_shift, UndistortionTable<float> undistortion);
  /// The rectified frame of `camera` for a frontend binning by 2^bin_shift.
  TrackingFrame(const CameraModel& camera, int bin_shift);

  bool rectified() const { return rectified_; }

  /// Position of binned pixel (x, y) (inside the binned image); false when it has none (its
  /// undistortion did not converge).
  bool position(int x, int y, float& fx, float& fy) const {
    if (!rectified_) {
      fx = static_cast<float>(x);
      fy = static_cast<float>(y);
      return true;
    }
    const std::size_t i = 2 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + x);
    fx = positions_[i];
    fy = positions_[i + 1];
    return fx == fx;  // NaN where there is none
  }

  /// Extent of the positions: the integer grid [0, gridWidth()) x [0, gridHeight()) holds every position
  /// minus (originX(), originY()) (registration table, dispatch grid).
  float originX() const { return origin_x_; }
  float originY() const { return origin_y_; }
  int gridWidth() const { return grid_width_; }
  int gridHeight() const { return grid_height_; }

  /// Whether a frame position lies inside the binned image, at least `margin` binned pixels from its
  /// border.
  bool inside(float x, float y, float margin) const;
  /// Whether (x, y) lies in a width x height image of pixel centres 0 .. size - 1, at least `margin` from
  /// its border.
  template <typename T>
  static bool withinMargin(T x, T y, int width, int height, T margin) {
    return x >= margin && y >= margin && x <= T(width - 1) - margin && y <= T(height - 1) - margin;
  }
  /// The cell of the registration grid holding a frame position (rounded, clamped to the grid).
  void gridCell(float x, float y, int& gx, int& gy) const {
    gx = std::clamp(static_cast<int>(std::lround(x - origin_x_)), 0, grid_width_ - 1);
    gy = std::clamp(static_cast<int>(std::lround(y - origin_y_)), 0, grid_height_ - 1);
  }

  /// The measurement of a frame position: its position in sensor pixels and its normalized undistorted
  /// coordinates; false when they are not available.
  bool measurement(float x, float y, float& sensor_x, float& sensor_y, float& xn, float& yn) const;

  /// Number of binned pixels without a position (0 for any sane calibration).
  int pixelsWithoutPosition() const { return without_position_; }

 private:
  /// Normalized coordinates of a rectified frame position: K_b^-1 (x, y, 1).
  Eigen::Vector2d normalized(float x, float y) const { return {(x - c_x_) / f_x_, (y - c_y_) / f_y_}; }

  int width_;   ///< binned image
  int height_;
  int bin_shift_;
  bool rectified_ = false;
  UndistortionTable<float> undistortion_;  ///< raw frame: sensor pixels -> normalized
  std::optional<CameraModel> camera_;      ///< rectified frame
  double f_x_ = 1, f_y_ = 1, c_x_ = 0, c_y_ = 0;  ///< K_b
  std::vector<float> positions_;           ///< rectified: (x, y) per binned pixel, row-major; NaN: none
  float origin_x_ = 0.f, origin_y_ = 0.f;
  int grid_width_ = 0, grid_height_ = 0;
  int without_position_ = 0;
};

}  // namespace asynevo::frontend
