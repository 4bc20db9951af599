#pragma once
// The direction audit (docs/method/depth_reversal.md, "Auditing a young segment"): after a start, the
// window's own motion between two times is compared on the chirality cost with its depth-reversed
// alternative. A start built on the reversed basin (the bas-relief / Necker ambiguity of narrow views)
// keeps a map whose inverse depths are mirrored and travels backwards through it; the window's later
// views see more of the scene than the start's span did, so they hold more evidence against it.

#include <cstdint>
#include <optional>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/backend/init_result.hpp"
#include "asynevo/backend/trajectory.hpp"

namespace asynevo::backend {

/// Compares the window's motion from t_a to t_b (its poses at the two times) with its depth-reversed
/// alternative, on the bearings of every trajectory observed on both sides of both times (its image
/// point interpolated there). The returned check has method "audit" and decision "kept"; nullopt when
/// fewer than min_features trajectories (at least 5) span both times, or when their median parallax once the
/// window's rotation is removed is below min_parallax_px (a rotation leaves the translation's direction,
/// and so its reversal, unobserved). focal converts angles to pixels, cauchy_px is the cost's Cauchy
/// scale.
std::optional<ReversalCheck> auditDirection(const Trajectory& window, const TrackMap& tracks, int64_t t_a_ns,
                                            int64_t t_b_ns, double focal, double cauchy_px, double min_parallax_px,
                                            int min_features);

}  // namespace asynevo::backend
