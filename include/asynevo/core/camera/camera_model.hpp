#pragma once
// Camera models: pinhole with radial-tangential (radtan / plumb-bob, k1 k2 p1 p2 k3) or equidistant
// (Kannala-Brandt fisheye, k1..k4) distortion. Formulas and sources: docs/camera_models.md.
//
// Coordinates used throughout:
//   raw pixel          (u, v): what the sensor reports; (0,0) is the top-left pixel centre.
//   distorted normalized (xd, yd) = ((u - cx) / fx, (v - cy) / fy).
//   normalized         (xn, yn) = (X / Z, Y / Z) of a point in the camera frame (undistorted).
//   bearing            unit vector (xn, yn, 1) / |(xn, yn, 1)|.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/camera/undistortion_table.hpp"

namespace asynevo {

enum class DistortionModel {
  kNone,         ///< ideal pinhole
  kRadtan,       ///< radial-tangential: k1 k2 p1 p2 k3 (OpenCV / Kalibr "radtan", ECD calib.txt)
  kEquidistant,  ///< equidistant fisheye: k1 k2 k3 k4 (OpenCV fisheye / Kalibr "equidistant")
};

/// "none", "radtan", "equidistant".
const char* distortionModelName(DistortionModel model);

/// Result of the iterative undistortion. `converged` is false when the iteration did not reach the
/// tolerance (or left the model's valid domain); `xn` then holds the last iterate and must not be used
/// as a measurement.
struct UndistortResult {
  Eigen::Vector2d xn = Eigen::Vector2d::Zero();
  bool converged = false;
  int iterations = 0;
  double residual = 0;  ///< |distort(xn) - xd| in normalized units at the last iterate
};

/// Settings of the iterative undistortion.
struct UndistortOptions {
  int max_iterations = 50;
  double tolerance = 1e-12;  ///< on |distort(xn) - xd| in normalized coordinates (~1e-10 px)
};

class CameraModel {
 public:
  /// Number of distortion coefficients of each model: none 0, radtan 5, equidistant 4.
  static int coefficientCount(DistortionModel model);

  /// Throws std::invalid_argument on a non-positive size or focal length, a non-finite value or a
  /// coefficient count that does not match the model (radtan also accepts 4, with k3 = 0).
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              DistortionModel model = DistortionModel::kNone, const std::vector<double>& coefficients = {});

  static CameraModel pinhole(int width, int height, double fx, double fy, double cx, double cy) {
    return CameraModel(width, height, fx, fy, cx, cy);
  }
  /// The ECD DAVIS240C calibration (Event Camera Dataset calib.txt, radtan), 240x180.
  static CameraModel davis240cEcd();

  int width() const { return width_; }
  int height() const { return height_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  DistortionModel distortionModel() const { return model_; }
  /// The model's coefficients: radtan {k1, k2, p1, p2, k3}, equidistant {k1, k2, k3, k4}, none {}.
  const std::vector<double>& coefficients() const { return coefficients_; }

  /// True when the raw pixel lies inside the image (centres 0..width-1, with half a pixel margin).
  bool inImage(const Eigen::Vector2d& pixel) const {
    return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < width_ - 0.5 && pixel.y() < height_ - 0.5;
  }

  /// Applies the distortion to normalized coordinates: (xn, yn) -> (xd, yd).
  Eigen::Vector2d distort(const Eigen::Vector2d& xn) const;
  /// d(distort)/d(xn), 2x2.
  Eigen::Matrix2d distortJacobian(const Eigen::Vector2d& xn) const;
  /// Inverts distort() iteratively (Gauss-Newton / Newton); reports non-convergence.
  UndistortResult undistort(const Eigen::Vector2d& xd, const UndistortOptions& options = {}) const;

  /// Normalized (undistorted) -> raw pixel.
  Eigen::Vector2d normalizedToPixel(const Eigen::Vector2d& xn) const {
    const Eigen::Vector2d xd = distort(xn);
    return {fx_ * xd.x() + cx_, fy_ * xd.y() + cy_};
  }
  /// Raw pixel -> distorted normalized coordinates (no undistortion).
  Eigen::Vector2d pixelToDistorted(const Eigen::Vector2d& pixel) const {
    return {(pixel.x() - cx_) / fx_, (pixel.y() - cy_) / fy_};
  }

  /// Projects a point in the camera frame to a raw pixel (with distortion). Returns nullopt when the
  /// point is not in front of the camera (Z <= min_depth); it does not check the image bounds.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_c, double min_depth = 1e-9) const;
  /// project() and its Jacobian d(pixel)/d(p_c) (2x3) in `J_pixel_p` (chain: intrinsics · distortion ·
  /// perspective division). Same validity as project().
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_c, Eigen::Matrix<double, 2, 3>* J_pixel_p,
                                         double min_depth = 1e-9) const;
  /// Raw pixel -> normalized undistorted coordinates; nullopt when the undistortion does not converge.
  std::optional<Eigen::Vector2d> unproject(const Eigen::Vector2d& pixel,
                                           const UndistortOptions& options = {}) const;
  /// Raw pixel -> unit bearing vector in the camera frame; nullopt when the undistortion does not converge.
  std::optional<Eigen::Vector3d> unprojectBearing(const Eigen::Vector2d& pixel,
                                                  const UndistortOptions& options = {}) const;

  /// Per-pixel undistortion table for the frontend's hot path: entry (x, y) holds unproject() of the
  /// pixel centre (x, y), or is marked invalid when the undistortion did not converge.
  template <typename Scalar>
  UndistortionTable<Scalar> undistortionTable(const UndistortOptions& options = {}) const;

  /// One line for logs: "240x180 fx=199.09 fy=198.83 cx=132.19 cy=110.71 radtan [-0.368 0.151 ...]".
  std::string summary() const;

 private:
  int width_;
  int height_;
  double fx_, fy_, cx_, cy_;
  DistortionModel model_;
  std::vector<double> coefficients_;
};

}  // namespace asynevo
