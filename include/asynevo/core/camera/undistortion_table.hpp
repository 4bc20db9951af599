#pragma once
// A W x H table of undistorted normalized coordinates, one entry per pixel centre, so the frontend
// turns a raw event pixel into (xn, yn) with one memory read instead of an iterative undistortion.
// Built by CameraModel::undistortionTable<Scalar>().

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace asynevo {

template <typename Scalar>
class UndistortionTable {
 public:
  using Vector2 = Eigen::Matrix<Scalar, 2, 1>;

  UndistortionTable() = default;
  UndistortionTable(int width, int height)
      : width_(width),
        height_(height),
        xy_(2 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height), Scalar(0)),
        valid_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0) {}

  int width() const { return width_; }
  int height() const { return height_; }

  /// Normalized undistorted coordinates of pixel (x, y). Undefined (zero) when !valid(x, y).
  Vector2 at(int x, int y) const {
    const std::size_t i = index(x, y);
    return {xy_[2 * i], xy_[2 * i + 1]};
  }
  Scalar xn(int x, int y) const { return xy_[2 * index(x, y)]; }
  Scalar yn(int x, int y) const { return xy_[2 * index(x, y) + 1]; }
  /// False for pixels whose undistortion did not converge (never silently garbage).
  bool valid(int x, int y) const { return valid_[index(x, y)] != 0; }
  /// Number of invalid pixels (0 for any sane calibration).
  std::size_t invalidCount() const {
    std::size_t n = 0;
    for (uint8_t v : valid_) n += v == 0 ? 1 : 0;
    return n;
  }

  void set(int x, int y, Scalar xn_value, Scalar yn_value, bool is_valid) {
    const std::size_t i = index(x, y);
    xy_[2 * i] = xn_value;
    xy_[2 * i + 1] = yn_value;
    valid_[i] = is_valid ? 1 : 0;
  }

  /// Interleaved (xn, yn) storage, row-major, 2*W*H values.
  const std::vector<Scalar>& data() const { return xy_; }

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  }

  int width_ = 0;
  int height_ = 0;
  std::vector<Scalar> xy_;
  std::vector<uint8_t> valid_;
};

}  // namespace asynevo
