#include "asynevo/eval/evaluate.hpp"

#include <fmt/format.h>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/eval/segments.hpp"
#include "asynevo/io/rosbag_topics.hpp"
#include "asynevo/io/trajectory_io.hpp"

namespace asynevo::eval {

namespace {

std::string seconds(int64_t t_ns) { return fmt::format("{:.3f}", nsToSeconds(t_ns)); }

void appendAll(std::vector<double>& to, const std::vector<double>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

void validate(const EvalOptions& options) {
  if (options.align_frames == 0 || options.align_frames < -1) {
    throw EvalError(
        fmt::format("--align-frames must be -1 (all) or at least 1, not {}", options.align_frames));
  }
  if (options.max_time_diff_ns <= 0) throw EvalError("the maximum association time difference must be > 0");
  for (double length : options.rel_lengths_m) {
    if (!(length > 0.0) || !std::isfinite(length)) {
      throw EvalError(fmt::format("relative-error length {} m is not a positive number", length));
    }
  }
  for (double pct : options.rel_percentages) {
    if (!(pct > 0.0) || !std::isfinite(pct)) {
      throw EvalError(fmt::format("relative-error percentage {} is not a positive fraction", pct));
    }
  }
}

void checkFinite(const StampedTrajectory& trajectory, const char* name) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const StampedPose& pose = trajectory[i];
    if (!pose.p_w_c.allFinite() || !pose.q_w_c.coeffs().allFinite()) {
      throw EvalError(
          fmt::format("{} pose {} (t = {} s) is not finite (NaN or infinity)", name, i, seconds(pose.t_ns)));
    }
    if (i > 0 && pose.t_ns < trajectory[i - 1].t_ns) {
      throw EvalError(
          fmt::format("{} pose {} (t = {} s) is earlier than the previous pose: poses must be sorted by time",
                      name, i, seconds(pose.t_ns)));
    }
  }
}

}  // namespace

EvalResult evaluate(const StampedTrajectory& gt, const StampedTrajectory& est, const EvalOptions& options) {
  validate(options);
  if (gt.empty()) throw EvalError("the ground truth has no poses");
  if (est.empty()) throw EvalError("the estimate has no poses");
  checkFinite(gt, "ground-truth");
  checkFinite(est, "estimate");

  EvalResult r;
  r.align = options.align;
  r.align_frames = options.align_frames;
  r.max_time_diff_ns = options.max_time_diff_ns;
  r.gt_poses = gt.size();
  r.est_poses = est.size();
  r.gt_t0_ns = gt.front().t_ns;
  r.gt_t1_ns = gt.back().t_ns;
  r.est_t0_ns = est.front().t_ns;
  r.est_t1_ns = est.back().t_ns;

  r.matches = associate(est, gt, options.max_time_diff_ns);
  r.matched = r.matches.size();
  const std::string spans = fmt::format(
      "the estimate spans {}–{} s ({} poses), the ground truth {}–{} s ({} poses)", seconds(r.est_t0_ns),
      seconds(r.est_t1_ns), r.est_poses, seconds(r.gt_t0_ns), seconds(r.gt_t1_ns), r.gt_poses);
  if (r.matched == 0) {
    const bool overlap = r.est_t0_ns <= r.gt_t1_ns && r.gt_t0_ns <= r.est_t1_ns;
    throw EvalError(fmt::format(
        "no estimate pose is within {} s of a ground-truth pose: {}{}", nsToSeconds(options.max_time_diff_ns),
        spans,
        overlap ? " (the ranges overlap but no times are close enough: different rates or a time offset?)"
                : " (the time ranges do not overlap: are both in the same time base?)"));
  }
  if (r.matched < 3) {
    throw EvalError(fmt::format("only {} pose(s) associated within {} s; at least 3 are needed: {}",
                                r.matched, nsToSeconds(options.max_time_diff_ns), spans));
  }
  if (r.matched < r.est_poses) {
    r.warnings.push_back(
        fmt::format("{} of {} estimate poses have no ground truth within {} s and are ignored",
                    r.est_poses - r.matched, r.est_poses, nsToSeconds(options.max_time_diff_ns)));
  }

  PosePairs& pairs = r.pairs;
  for (const Match& m : r.matches) {
    pairs.p_est.push_back(est[m.est].p_w_c);
    pairs.R_est.push_back(est[m.est].q_w_c.toRotationMatrix());
    pairs.p_gt.push_back(gt[m.gt].p_w_c);
    pairs.R_gt.push_back(gt[m.gt].q_w_c.toRotationMatrix());
    pairs.t_gt_ns.push_back(gt[m.gt].t_ns);
  }

  // Path length of the whole ground truth (rpg: p_gt_raw), which the percentages refer to.
  std::vector<Eigen::Vector3d> gt_positions;
  gt_positions.reserve(gt.size());
  for (const auto& pose : gt) gt_positions.push_back(pose.p_w_c);
  r.gt_path_length_m = distancesFromStart(gt_positions).back();
  const std::vector<double> distances = distancesFromStart(pairs.p_gt);
  r.matched_gt_path_length_m = distances.back();

  r.alignment =
      alignTrajectory(pairs.p_est, pairs.R_est, pairs.p_gt, pairs.R_gt, options.align, options.align_frames);
  if (!std::isfinite(r.alignment.scale) || !r.alignment.rotation.allFinite() ||
      !r.alignment.translation.allFinite()) {
    throw EvalError("the alignment is not finite (degenerate trajectories?)");
  }
  if (options.align == AlignType::kSim3 && !(r.alignment.scale > 0.0)) {
    throw EvalError(
        fmt::format("the Sim(3) alignment scale is {} (degenerate estimate?)", r.alignment.scale));
  }
  r.ate = computeAbsoluteErrors(pairs, r.alignment);

  const std::vector<double> lengths =
      options.rel_lengths_m.empty() ? lengthsFromPercentages(r.gt_path_length_m, options.rel_percentages)
                                    : options.rel_lengths_m;
  RelativeErrorOptions rel_options;
  rel_options.rpg_start_indexing = options.rpg_start_indexing;
  std::vector<double> all_trans, all_perc, all_rot;
  for (double length : lengths) {
    if (!(length > 0.0)) {
      r.warnings.push_back(
          fmt::format("sub-trajectory length {} m skipped (the ground-truth path, {:.4f} m, is too "
                      "short for 2-decimal lengths)",
                      length, r.gt_path_length_m));
      continue;
    }
    RelativeErrors rel = computeRelativeErrors(pairs, distances, length, r.alignment.scale, rel_options);
    if (rel.too_few) {
      r.warnings.push_back(
          fmt::format("sub-trajectory length {} m: fewer than 2 sub-trajectories (the associated ground "
                      "truth travels {:.3f} m)",
                      length, r.matched_gt_path_length_m));
    }
    if (rel.shifted_starts > 0) {
      r.warnings.push_back(
          fmt::format("sub-trajectory length {} m: {} sample(s) use rpg's shifted start index (a "
                      "start without an end lies before them)",
                      length, rel.shifted_starts));
    }
    appendAll(all_trans, rel.trans_m);
    appendAll(all_perc, rel.trans_perc);
    appendAll(all_rot, rel.rot_deg);
    r.relative.push_back(std::move(rel));
  }
  r.pooled_trans = computeStats(all_trans);
  r.pooled_trans_perc = computeStats(all_perc);
  r.pooled_rot = computeStats(all_rot);
  return r;
}

void addVelocityErrors(EvalResult& result, const StampedTrajectory& gt,
                       const std::vector<StampedTwist>& twists, const EvalOptions& options,
                       const std::string& source) {
  result.velocity = computeVelocityErrors(gt, twists, result.alignment.scale, options.velocity_max_gt_gap_ns);
  const VelocityErrors& v = *result.velocity;
  if (v.samples == 0) {
    result.warnings.push_back(fmt::format(
        "{}: none of the {} twists has a ground-truth velocity (outside the ground truth's time span, or "
        "its poses are more than {} s apart there): no velocity error",
        source, v.est_twists, nsToSeconds(options.velocity_max_gt_gap_ns)));
  } else if (v.samples < v.est_twists) {
    result.warnings.push_back(fmt::format(
        "{}: {} of {} twists have no ground-truth velocity (outside its time span or across a "
        "gap > {} s) and are ignored",
        source, v.est_twists - v.samples, v.est_twists, nsToSeconds(options.velocity_max_gt_gap_ns)));
  }
}

EvalResult evaluateFiles(const std::string& gt_path, const std::string& est_path, const EvalOptions& options,
                         const std::string& velocities_path, const std::string& segments_path) {
  TrajectoryReadReport gt_report, est_report;
  StampedTrajectory gt;
  if (isRosbag(gt_path)) {  // a bag's pose topic (docs/reference/formats_rosbag.md#ground-truth)
    std::optional<BagGroundTruth> poses = readRosbagGroundTruth(gt_path, options.gt_topic);
    if (!poses) {
      throw InputError(gt_path, "the bag has no pose topic (geometry_msgs/PoseStamped, geometry_msgs/TransformStamped "
                                "or nav_msgs/Odometry)");
    }
    gt = std::move(poses->poses);
  } else {
    if (!options.gt_topic.empty())
      throw InputError(gt_path, "--gt-topic names a topic of a ROS bag, but the ground-truth file is not a ROS bag");
    gt = readTumTrajectory(gt_path, &gt_report);
  }
  const StampedTrajectory est = readTumTrajectory(est_path, &est_report);
  const std::vector<StampedTwist> twists =
      velocities_path.empty() ? std::vector<StampedTwist>{} : readVelocities(velocities_path);
  const std::vector<EstimateSegment> segments =
      segments_path.empty() ? std::vector<EstimateSegment>{} : readSegments(segments_path);
  EvalResult result;
  try {
    if (segments.empty()) {
      result = evaluate(gt, est, options);
      if (!velocities_path.empty()) addVelocityErrors(result, gt, twists, options, velocities_path);
    } else {
      result = evaluateSegmented(gt, est, segments, options, velocities_path.empty() ? nullptr : &twists);
    }
    if (!velocities_path.empty()) result.velocities_path = velocities_path;
  } catch (const EvalError& e) {
    throw EvalError(fmt::format("{} vs {}: {}", est_path, gt_path, e.what()));
  }
  for (const auto& [path, report] : {std::pair{&gt_path, &gt_report}, std::pair{&est_path, &est_report}}) {
    if (report->normalized_quaternions > 0) {
      result.warnings.insert(
          result.warnings.begin(),
          fmt::format("{}: {} quaternion(s) were not unit length and were normalized (first at "
                      "line {}, largest |norm - 1| = {:.3g})",
                      *path, report->normalized_quaternions, report->first_normalized_line,
                      report->max_quaternion_norm_error));
    }
  }
  return result;
}

}  // namespace asynevo::eval
