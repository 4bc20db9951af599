#pragma once
// Body-velocity error of an estimated twist sequence (a run folder's velocities.txt) against the
// velocity of the ground-truth poses (docs/evaluation.md, "Velocity error"):
//
//   ground truth: central differences of neighbouring poses i−1, i+1 (both within `max_gt_gap_ns` of
//     pose i): v_g,i = R_iᵀ (p_i+1 − p_i−1) / (t_i+1 − t_i−1), ω_g,i = Log(R_i−1ᵀ R_i+1) / (t_i+1 − t_i−1),
//     linearly interpolated at the estimate's times between two such samples at most `max_gt_gap_ns`
//     apart (or taken as is at an equal time);
//   error per twist: ‖s v_e − v_g‖ (linear, s = the alignment scale) and ‖ω_e − ω_g‖ (angular, deg/s);
//   direction of travel per twist: the angle between v_e and v_g (deg), where the ground truth moves at
//     least kDirectionMinSpeedFraction of its mean speed; an angle above 90° is travel in reverse.
//     Scale- and alignment-free, it catches an estimate whose camera moves backwards through a
//     depth-inverted map (the rotation–translation ambiguity of a monocular start or of a collapsed
//     scale), which a Sim(3) fit of positions alone can score at a few % ATE.
//
// The body-frame twist does not depend on the alignment's rotation and translation; its linear part
// carries the estimate's map scale, hence s.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/eval/statistics.hpp"

namespace asynevo::eval {

/// Ground-truth poses further apart than this are not differentiated across (a hole in the ground
/// truth); 0.1 s spans 1 kHz simulation, ~200 Hz mocap and 10–20 Hz odometry ground truth.
constexpr int64_t kDefaultVelocityMaxGtGapNs = 100'000'000;

/// The direction of travel is scored where the ground truth moves at least this share of its mean
/// speed (near a stop or a reversal its direction is not defined).
constexpr double kDirectionMinSpeedFraction = 0.25;

struct VelocityErrors {
  double scale = 1.0;              ///< applied to the estimate's linear velocity
  std::size_t est_twists = 0;      ///< twists in the input
  std::size_t samples = 0;         ///< twists with a ground-truth velocity (the rest are outside it)
  Stats linear_mps;                ///< ‖s v_e − v_g‖ per sample [m/s]
  Stats angular_dps;               ///< ‖ω_e − ω_g‖ per sample [deg/s]
  double mean_gt_speed_mps = 0.0;  ///< mean ‖v_g‖ over the samples
  double mean_gt_rate_dps = 0.0;   ///< mean ‖ω_g‖ over the samples [deg/s]
  /// linear_mps.rmse / mean_gt_speed_mps · 100 (issue 7's target: ≤ 10); NaN when the mean speed is 0.
  double linear_rmse_perc = 0.0;
  /// angular_dps.rmse / mean_gt_rate_dps · 100; NaN when the mean rate is 0.
  double angular_rmse_perc = 0.0;
  /// Angle between v_e and v_g per sample where ‖v_g‖ ≥ kDirectionMinSpeedFraction · mean speed [deg].
  Stats direction_deg;
  /// Share of those samples travelling in reverse (angle > 90°); NaN when there is none.
  double reversed_fraction = 0.0;
  std::vector<double> t_s;  ///< sample times [s]
};

/// Velocity errors of `twists` (body frame, estimate map units) against the body velocity of `gt`
/// (sorted by time). Twists without a ground-truth velocity are left out (samples < est_twists);
/// with no sample at all every Stats has num_samples = 0. Throws EvalError for a ground truth that
/// is not sorted by time, a non-finite or non-positive scale or max_gt_gap_ns <= 0.
VelocityErrors computeVelocityErrors(const StampedTrajectory& gt, const std::vector<StampedTwist>& twists,
                                     double scale, int64_t max_gt_gap_ns = kDefaultVelocityMaxGtGapNs);

/// `velocities.txt` in the folder of `est_path` (a run folder's estimate) if that file exists, else "".
std::string velocitiesBesideEstimate(const std::string& est_path);

}  // namespace asynevo::eval
