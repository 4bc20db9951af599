#pragma once
// The first knots of a segment, built from the start's motion (docs/method/initialization.md, "First
// knots"): knots on the knot grid at the start's constant twist, then, optionally, each knot's rotation
// fitted to the feature tracks. A constant twist is only a model of the motion over the window; under
// hand-held rotation of 100–250 deg/s that changes within it, the constant-twist knots are off by
// degrees, the landmarks triangulated from them miss the reprojection bound, and the start is rejected
// for too few landmarks although its motion was right.

#include <cstdint>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/backend/init_result.hpp"
#include "asynevo/backend/trajectory.hpp"

namespace asynevo::backend {

/// Knots every knot_dt_ns from motion.t_a_ns up to t_end_ns on exp(τ ξ), ξ the twist of motion.T_a_b
/// over its span, with the translation scaled so that the mean speed over the span is 1 map unit per
/// second (the monocular scale rule). Each knot's velocity is ξ.
Trajectory constantTwistTrajectory(const InitResult& motion, int64_t t_end_ns, int64_t knot_dt_ns);

/// The direction of travel of the start's constant twist in the body frame (the unit translational
/// part ρ/|ρ| of ξ = log(T_a_b)/span): under a constant twist it is the same at every time of the span,
/// so the motions two attempts found over different spans can be compared.
lie::Vec3 startTravelDirection(const InitResult& motion);

/// The angle between two start motions' travel directions (startTravelDirection), in degrees.
double travelAngleDeg(const InitResult& a, const InitResult& b);

struct RotationRefinement {
  int intervals = 0;          ///< knot intervals
  int refined = 0;            ///< knots whose rotation was fitted (those seen by enough features)
  double max_change_deg = 0;  ///< the largest change of a knot's rotation
};

/// Refits the knots' rotations to the feature tracks sampled at the knot times: a small bundle
/// adjustment over the rotations and each feature's inverse depth along its first bearing, on the
/// reprojection errors (Cauchy loss at scale c, rad), with a smoothness prior on the rotations (one
/// sigma: 20 rad/s² of angular acceleration). Positions are held, so the start's baseline and scale are
/// unchanged; the first knot is held (gauge). Seeded by the current knots; velocities become the twists
/// between neighbour knots. Nothing changes when no knot after the first is seen by kMinRefitFeatures
/// features; `refined` counts those that are.
RotationRefinement refineStartRotations(Trajectory& trajectory, const TrackMap& tracks, double c);

inline constexpr int kMinRefitFeatures = 8;

}  // namespace asynevo::backend
