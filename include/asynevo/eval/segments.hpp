#pragma once
// Evaluation of an estimate made of segments (docs/method/tracking_loss.md): after a tracking loss the
// estimator starts again with a new map whose scale and gauge are unrelated to the previous one, so
// each segment gets its own alignment (as a separate run would) and the errors of all segments are
// then pooled. Relative errors use sub-trajectories inside one segment only; coverage is the share of
// the ground truth's time span that the segments cover.

#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/eval/evaluate.hpp"
#include "asynevo/eval/velocity_errors.hpp"

namespace asynevo::eval {

/// One line of a run's segments.txt: `index start_s end_s knots ended_by`.
struct EstimateSegment {
  int index = 0;
  int64_t t0_ns = 0, t1_ns = 0;  ///< first and last knot time
  uint64_t knots = 0;
  std::string ended_by;  ///< why the estimator ended it (end_of_stream for the last one)
};

/// Reads a segments.txt (`#` comments; fields `index start_s end_s knots ended_by`). Throws InputError
/// naming the file and line for a malformed line, segments that overlap or go back in time, or an
/// empty file.
std::vector<EstimateSegment> readSegments(const std::string& path);

/// segments.txt in the estimate's folder when it exists, else "".
std::string segmentsBesideEstimate(const std::string& est_path);

/// Evaluates `est` segment by segment (each with options.align, on its own poses), then pools: ATE and
/// the pairs use each pose aligned by its own segment's similarity (EvalResult::alignment is then the
/// identity and EvalResult::segments holds each one), relative errors take sub-trajectories inside a
/// segment, velocity errors scale each twist by its segment's scale. A segment with fewer than 3
/// associated poses is listed as not scored (with the reason) and left out of the errors. Estimate
/// poses outside every segment are an EvalError. With one segment this equals evaluate() plus coverage.
EvalResult evaluateSegmented(const StampedTrajectory& gt, const StampedTrajectory& est,
                             const std::vector<EstimateSegment>& segments, const EvalOptions& options,
                             const std::vector<StampedTwist>* twists = nullptr);

}  // namespace asynevo::eval
