#pragma once
// Multi-view initialization (docs/method/initialization.md, "Multi-view start"): one constant body
// twist fitted to every feature trajectory of the window at once, so that no feature has to be seen at
// both ends of the span. Each feature's position is sampled on a grid over the window; every sample
// after its first gives an epipolar constraint with the first, the relative pose between two times
// being exp(Δt ξ) for the twist ξ = (ρ, φ) (Barfoot, State Estimation for Robotics, 2017, §7.1.9: the
// SE(3) exponential). The rotation rate φ is seeded by a rotation-only fit, the translation direction ρ
// by the smallest eigenvector of the epipolar constraints that are linear in it once φ is known (the
// eigenvalue formulation of Kneip & Lynen, "Direct optimization of frame-to-frame rotation", ICCV
// 2013, here over many times at once), and both are refined together on the angular epipolar errors
// under a Cauchy loss. The sign of ρ is the one that puts more points in front of the cameras; the
// checks and the scale rule are those of the two-view start.

#include <cstdint>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/backend/init_result.hpp"
#include "asynevo/core/config/backend_config.hpp"

namespace asynevo::backend {

/// Grid intervals over the window at which each feature's position is sampled.
inline constexpr int kMultiViewSteps = 10;

/// Fits one constant twist to all tracks over [max(earliest_ns, t_b_ns − init_window_ms), t_b_ns].
/// The result's T_a_b is exp(span × ξ) with its translation scaled to 1; `features` counts the tracks
/// with at least two samples, `inliers` those that fit and are not behind a camera.
InitResult initializeMultiView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                               const BackendConfig& config);

}  // namespace asynevo::backend
