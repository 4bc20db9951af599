#pragma once
// A W x H table of undistorted normalized coordinates, one entry per pixel centre, so the frontend
// turns a raw event pixel into (xn, yn) with one memory read instead of an iterative undistortion.
// Built by CameraModel::undistortionTable<Scalar>().

#include <Eigen/Core>
#include <algorithm>
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

  /// Bilinear interpolation at a sub-pixel position (x, y) inside the sensor; false outside it or when
  /// one of the four surrounding entries is invalid.
  bool interpolate(Scalar x, Scalar y, Scalar& xn_out, Scalar& yn_out) const {
    if (!(x >= Scalar(0) && y >= Scalar(0) && x <= Scalar(width_ - 1) && y <= Scalar(height_ - 1))) return false;
    const int x0 = std::min(static_cast<int>(x), width_ - 2), y0 = std::min(static_cast<int>(y), height_ - 2);
    const Scalar fx = x - Scalar(x0), fy = y - Scalar(y0);
    if (!valid(x0, y0) || !valid(x0 + 1, y0) || !valid(x0, y0 + 1) || !valid(x0 + 1, y0 + 1)) return false;
    const Scalar w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
    xn_out = w00 * xn(x0, y0) + w10 * xn(x0 + 1, y0) + w01 * xn(x0, y0 + 1) + w11 * xn(x0 + 1, y0 + 1);
    yn_out = w00 * yn(x0, y0) + w10 * yn(x0 + 1, y0) + w01 * yn(x0, y0 + 1) + w11 * yn(x0 + 1, y0 + 1);
    return true;
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
