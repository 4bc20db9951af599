#pragma once
// Monocular two-view initialization from feature trajectories (DESIGN.md §4 Initialization):
// pick two times t_a < t_b with enough features seen at both and enough image motion, estimate the
// relative pose with the five-point algorithm in RANSAC (OpenCV findEssentialMat; Nistér, PAMI 2004),
// choose among the four decompositions of E by the points in front of both cameras (far points neither
// vote nor count against), accept it only with enough parallax once the rotation is removed (the median
// inlier ray angle), and fix the monocular scale by a unit baseline between the two times.

#include <cstdint>
#include <string>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/core/config/backend_config.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

struct TwoViewResult {
  bool ok = false;
  std::string failure;  ///< when !ok: which check failed, with the counts
  int64_t t_a_ns = 0;
  int64_t t_b_ns = 0;
  lie::SE3 T_a_b;       ///< camera at t_b in the frame of the camera at t_a, |t| = 1
  int features = 0;     ///< features seen at both times
  int inliers = 0;
  double parallax_px = 0;  ///< median inlier parallax (rotation removed) between the two times, pixels
};

/// Number of candidate spans: init_window_ms × k / kInitSpans for k = kInitSpans .. 1.
inline constexpr int kInitSpans = 6;

/// Tries every candidate span ending at t_b_ns (starting no earlier than `earliest_ns`) and returns the
/// one that passes every check with the best score, parallax × sqrt(inliers); when none passes, the
/// failure of each span. `focal` converts normalized units to pixels for the thresholds.
TwoViewResult initializeTwoView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                                const BackendConfig& config);

/// The checks and the pose for one span, t_a .. t_b.
TwoViewResult initializeTwoViewSpan(const TrackMap& tracks, int64_t t_a, int64_t t_b, double focal,
                                    const BackendConfig& config);

}  // namespace asynevo::backend
