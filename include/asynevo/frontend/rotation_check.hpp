#pragma once
// Accuracy check of feature tracks recorded under (nearly) pure camera rotation, without ground-truth
// tracks: under pure rotation every undistorted bearing moves by one common rotation,
// x(t) ~ K R(t)^T R(t_j) K^-1 x(t_j), whatever the depth. One smooth rotation model (constant angular
// velocity, optionally with constant angular acceleration) is fitted to all tracks jointly by robust
// (Huber) least squares, with a free initial bearing per track; the per-measurement residuals measure
// tracking error (plus model error, small on 13-99 ms slices). Used on the ECD rotation slices
// (docs/frontend.md "Accuracy").

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "asynevo/frontend/track_measurement.hpp"

namespace asynevo::frontend {

struct RotationFitOptions {
  bool with_acceleration = false;  ///< fit a constant angular acceleration as well
  double huber_px = 1.0;           ///< Huber threshold on the residual norm (undistorted pixels)
  int iterations = 30;             ///< Gauss-Newton iterations at most
  int min_measurements = 3;        ///< tracks with fewer measurements are not used (they fit exactly)
};

struct RotationFitResult {
  /// Camera angular velocity (rad/s, camera frame) at t_ref: R_w_c(t) = R_w_c(t_ref) Exp(omega tau + alpha
  /// tau^2/2).
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();  ///< rad/s^2 (zero unless fitted)
  int64_t t_ref_ns = 0;                             ///< middle of the measurements' time span
  int tracks_used = 0;
  int tracks_excluded = 0;           ///< fewer than min_measurements
  int measurements = 0;              ///< measurements of the used tracks
  std::vector<double> residuals_px;  ///< norm of each used measurement's residual (undistorted px)
  double median_px = 0, p90_px = 0, rms_px = 0;
  double share_above_3px = 0;
  double lifetime_median_s = 0, lifetime_mean_s = 0, lifetime_max_s = 0;  ///< of the used tracks
  int iterations = 0;
};

/// Fits the rotation model to `measurements` (their normalized coordinates xn, yn are used); fx, fy
/// express the residuals in pixels. Throws std::invalid_argument when fewer than 2 tracks are usable.
RotationFitResult fitCommonRotation(const std::vector<TrackMeasurement>& measurements, double fx, double fy,
                                    const RotationFitOptions& options = {});

}  // namespace asynevo::frontend
