#pragma once
// One evaluation of an estimated trajectory against ground truth, as rpg_trajectory_evaluation
// does it for one result folder: associate (0.02 s), align (sim3 by default, all frames), absolute
// errors (ATE) of the aligned estimate, relative errors at sub-trajectory lengths of 10 … 50 % of
// the ground-truth path length (or given lengths), pooled relative errors over all lengths.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/eval/alignment.hpp"
#include "asynevo/eval/association.hpp"
#include "asynevo/eval/statistics.hpp"
#include "asynevo/eval/trajectory_errors.hpp"
#include "asynevo/eval/velocity_errors.hpp"

namespace asynevo::eval {

struct EvalOptions {
  AlignType align = AlignType::kSim3;
  int align_frames = -1;  ///< −1 = all associated poses
  int64_t max_time_diff_ns = kDefaultMaxTimeDiffNs;
  std::vector<double> rel_lengths_m;  ///< given lengths (m); empty = use percentages
  std::vector<double> rel_percentages = {0.1, 0.2, 0.3, 0.4, 0.5};  ///< of the GT path length
  bool rpg_start_indexing = true;                                   ///< see RelativeErrorOptions
  int64_t velocity_max_gt_gap_ns = kDefaultVelocityMaxGtGapNs;      ///< see computeVelocityErrors
  /// When the ground truth is a ROS bag: its pose topic ("" = the bag's only one).
  std::string gt_topic;
};

/// One segment of a segmented estimate (segments.hpp), aligned on its own.
struct SegmentResult {
  int index = 0;
  int64_t t0_ns = 0, t1_ns = 0;
  std::string ended_by;
  std::size_t poses = 0, matched = 0;
  Similarity alignment;
  double ate_rmse_m = 0.0;
  bool scored = false;
  std::string note;  ///< why it was not scored
};

struct EvalResult {
  AlignType align = AlignType::kSim3;
  int align_frames = -1;
  int64_t max_time_diff_ns = kDefaultMaxTimeDiffNs;

  std::size_t gt_poses = 0, est_poses = 0, matched = 0;
  int64_t gt_t0_ns = 0, gt_t1_ns = 0, est_t0_ns = 0, est_t1_ns = 0;  ///< time spans of the inputs
  double gt_path_length_m = 0.0;          ///< whole ground truth (rpg: percentages refer to this)
  double matched_gt_path_length_m = 0.0;  ///< associated ground-truth poses only

  PosePairs pairs;  ///< associated poses (unaligned estimate)
  std::vector<Match> matches;
  Similarity alignment;
  AbsoluteErrors ate;
  std::vector<RelativeErrors> relative;               ///< one per length, in the order requested
  Stats pooled_trans, pooled_trans_perc, pooled_rot;  ///< all lengths' samples together

  /// Body-velocity errors (addVelocityErrors), when the estimate's twists were given.
  std::optional<VelocityErrors> velocity;
  std::string velocities_path;  ///< where the twists came from ("" for in-memory input)

  std::vector<std::string> warnings;  ///< things a user should know (shown by the CLI)

  /// With a segments file (evaluateSegmented): each segment's own alignment and score, and the share
  /// of the ground truth's time span the segments cover. Empty / unset otherwise.
  std::vector<SegmentResult> segments;
  std::optional<double> coverage;
};

/// Evaluates `est` against `gt`. Throws EvalError when nothing associates (with both time spans in
/// the message, saying whether they overlap), when fewer than 3 poses associate, or on invalid
/// options.
EvalResult evaluate(const StampedTrajectory& gt, const StampedTrajectory& est, const EvalOptions& options);

/// Adds the body-velocity errors of `twists` against `gt` to `result` (computed by evaluate() from
/// the same ground truth): the linear part is scaled by result.alignment.scale (1 unless sim3). A
/// warning says how many twists have no ground-truth velocity; `source` names them in it.
void addVelocityErrors(EvalResult& result, const StampedTrajectory& gt,
                       const std::vector<StampedTwist>& twists, const EvalOptions& options,
                       const std::string& source = "the velocities");

/// Reads both files (TUM / ECD layout) and evaluates. Reader warnings (normalized quaternions) and
/// association problems name the files. With `velocities_path` (a velocities.txt: t vx vy vz wx wy wz,
/// body frame) also the velocity errors (addVelocityErrors). With `segments_path` (a run's
/// segments.txt) each segment is aligned on its own (evaluateSegmented).
EvalResult evaluateFiles(const std::string& gt_path, const std::string& est_path, const EvalOptions& options,
                         const std::string& velocities_path = "", const std::string& segments_path = "");

}  // namespace asynevo::eval
