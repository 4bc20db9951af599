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
#include "asynevo/backend/init_result.hpp"
#include "asynevo/core/config/backend_config.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {


/// Number of candidate spans: init_window_ms × k / kInitSpans for k = kInitSpans .. 1.
inline constexpr int kInitSpans = 6;

/// Tries every candidate span ending at t_b_ns (starting no earlier than `earliest_ns`) and returns the
/// one that passes every check with the best score, parallax × sqrt(inliers); when none passes, the
/// failure of each span and, as its rejection, the furthest check any span reached. `focal` converts normalized units to pixels for the thresholds.
InitResult initializeTwoView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                                const BackendConfig& config);

/// The checks and the pose for one span, t_a .. t_b.
InitResult initializeTwoViewSpan(const TrackMap& tracks, int64_t t_a, int64_t t_b, double focal,
                                    const BackendConfig& config);

}  // namespace asynevo::backend
