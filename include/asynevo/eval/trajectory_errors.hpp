#pragma once
// Absolute and relative trajectory errors with rpg_trajectory_evaluation's definitions
// (compute_trajectory_errors.py, trajectory_utils.py, trajectory.py; docs/evaluation.md pins the
// version). Inputs are associated pose pairs: index i of the estimate belongs with index i of the
// ground truth.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "asynevo/eval/alignment.hpp"
#include "asynevo/eval/statistics.hpp"

namespace asynevo::eval {

/// Associated poses as rotation matrices and positions (T_w_c).
struct PosePairs {
  std::vector<Eigen::Vector3d> p_est, p_gt;
  std::vector<Eigen::Matrix3d> R_est, R_gt;
  std::vector<int64_t> t_gt_ns;  ///< ground-truth time of each pair
  std::size_t size() const { return p_est.size(); }
};

/// Per-pose absolute errors after alignment.
struct AbsoluteErrors {
  std::vector<double> trans_m;  ///< ‖p_gt − (s R p_est + t)‖
  std::vector<double> rot_deg;  ///< angle of (R R_est)·R_gtᵀ, as rpg (logmap norm)
  std::vector<double> scale_perc;  ///< rpg's "scale" error: |‖p_est,aligned‖/‖p_gt‖ − 1|·100 (see docs)
  Stats trans, rot, scale;
};

AbsoluteErrors computeAbsoluteErrors(const PosePairs& pairs, const Similarity& alignment);

/// Travelled distance from the first position: d_0 = 0, d_k = d_{k−1} + ‖p_k − p_{k−1}‖.
std::vector<double> distancesFromStart(const std::vector<Eigen::Vector3d>& positions);

/// Sub-trajectory end indices as rpg's compute_comparison_indices_length: for each start i with
/// travelled distance d_i, the index j ≥ i whose d_j is closest to d_i + length with
/// |d_j − (d_i + length)| < max_dist_diff (first such index on ties). Starts without such a j are
/// omitted, so the result lists end indices of the starts that have one, in start order.
std::vector<std::size_t> comparisonIndices(const std::vector<double>& distances, double length,
                                           double max_dist_diff);

/// rpg's default sub-trajectory lengths: trunc(pct · path_length, 2 decimals) for each pct.
std::vector<double> lengthsFromPercentages(double path_length, const std::vector<double>& percentages);

/// Relative errors for one sub-trajectory length.
struct RelativeErrors {
  double length_m = 0.0;
  double max_dist_diff_m = 0.0;
  std::vector<std::size_t> start, end;  ///< pair indices of each sample
  std::vector<double> trans_m, trans_perc, rot_deg, yaw_deg, gravity_deg, rot_deg_per_m;
  Stats trans, trans_perc_stats, rot, yaw, gravity, rot_per_m;
  std::size_t shifted_starts = 0;  ///< starts the rpg indexing quirk shifted (see RelativeErrorOptions)
  bool too_few = false;            ///< fewer than 2 sub-trajectories: rpg computes nothing
};

struct RelativeErrorOptions {
  /// rpg pairs the k-th found end index with start k (not with its own start) whenever an earlier
  /// start has no end within tolerance. true reproduces the toolbox's numbers exactly; false pairs
  /// each end with its own start. Both agree when no start in the middle lacks an end.
  bool rpg_start_indexing = true;
};

/// Relative error at sub-trajectory length `length` (m) with tolerance 0.2·length, the estimate's
/// relative translation multiplied by `scale` (the Sim(3) alignment scale; 1 otherwise), using
/// travelled distances `distances` of the associated ground truth. Error transform
/// E = (T_gt,i⁻¹ T_gt,j)⁻¹ (T_est,i⁻¹ T_est,j) rotated into the world frame by R_est,j.
/// Fills the statistics of `e` (trans, trans_perc_stats, rot, yaw, gravity, rot_per_m) from its samples.
void computeRelativeStats(RelativeErrors& e);

RelativeErrors computeRelativeErrors(const PosePairs& pairs, const std::vector<double>& distances,
                                     double length, double scale, const RelativeErrorOptions& options = {});

}  // namespace asynevo::eval
