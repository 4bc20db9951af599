#pragma once
// Timestamp association, as rpg_trajectory_evaluation's associate_timestamps.associate (itself the
// TUM RGB-D benchmark's associate.py): every (estimate, ground truth) pair whose times differ by
// less than max_diff is a candidate; candidates are sorted by |Δt| (ties: by estimate index, then
// ground-truth index), accepted greedily so each pose is used at most once, and the accepted pairs
// are sorted by estimate index. Times are compared in exact integer nanoseconds.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"

namespace asynevo::eval {

/// Default maximum time difference: 0.02 s, as rpg_trajectory_evaluation.
constexpr int64_t kDefaultMaxTimeDiffNs = 20'000'000;

struct Match {
  std::size_t est = 0;  ///< index into the estimate
  std::size_t gt = 0;   ///< index into the ground truth
};

/// Associates two timestamp lists (each sorted, non-decreasing). Pairs with |t_est - t_gt| <
/// max_diff_ns (strict) are candidates.
std::vector<Match> associate(const std::vector<int64_t>& est_t_ns, const std::vector<int64_t>& gt_t_ns,
                             int64_t max_diff_ns = kDefaultMaxTimeDiffNs);

/// Same, on trajectories.
std::vector<Match> associate(const StampedTrajectory& est, const StampedTrajectory& gt,
                             int64_t max_diff_ns = kDefaultMaxTimeDiffNs);

}  // namespace asynevo::eval
