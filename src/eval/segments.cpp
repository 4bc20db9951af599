#include "asynevo/eval/segments.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::eval {

namespace {

// Times in segments.txt and the trajectory files are printed with 9 decimals; a pose belongs to a
// segment when it lies within its span up to this rounding slack.
constexpr int64_t kSlackNs = 1000;

bool inSegment(int64_t t_ns, const EstimateSegment& s) { return t_ns >= s.t0_ns - kSlackNs && t_ns <= s.t1_ns + kSlackNs; }

// The share of the ground truth's time span inside a segment.
double coverageOf(const std::vector<EstimateSegment>& segments, const StampedTrajectory& gt) {
  int64_t covered = 0;
  for (const EstimateSegment& s : segments) {
    const int64_t a = std::max(s.t0_ns, gt.front().t_ns), b = std::min(s.t1_ns, gt.back().t_ns);
    if (b > a) covered += b - a;
  }
  const int64_t span = gt.back().t_ns - gt.front().t_ns;
  return span > 0 ? static_cast<double>(covered) / static_cast<double>(span) : 0.0;
}

void appendAll(std::vector<double>& to, const std::vector<double>& from) { to.insert(to.end(), from.begin(), from.end()); }

}  // namespace

std::vector<EstimateSegment> readSegments(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open the segments file");
  std::vector<EstimateSegment> segments;
  std::string line;
  uint64_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    EstimateSegment s;
    double t0 = 0, t1 = 0;
    std::string extra;
    if (!(fields >> s.index >> t0 >> t1 >> s.knots >> s.ended_by) || (fields >> extra)) {
      throw InputError::atLine(path, number, "expected 5 fields: index start_s end_s knots ended_by");
    }
    // 1e9 s (31 years) bounds the times so that they convert to int64 nanoseconds exactly enough.
    if (!std::isfinite(t0) || !std::isfinite(t1) || t1 < t0 || std::abs(t0) > 1e9 || std::abs(t1) > 1e9) {
      throw InputError::atLine(path, number, fmt::format("segment times {} .. {} s are not an interval", t0, t1));
    }
    s.t0_ns = secondsToNs(t0);
    s.t1_ns = secondsToNs(t1);
    if (!segments.empty() && s.t0_ns <= segments.back().t1_ns) {
      throw InputError::atLine(path, number,
                               fmt::format("segment {} starts at {} s, not after the previous one ends ({} s)",
                                           s.index, t0, nsToSeconds(segments.back().t1_ns)));
    }
    segments.push_back(s);
  }
  if (in.bad()) throw InputError(path, "read failed");
  if (segments.empty()) throw InputError(path, "no segment in the file");
  return segments;
}

std::string segmentsBesideEstimate(const std::string& est_path) {
  const std::filesystem::path p = std::filesystem::path(est_path).parent_path() / "segments.txt";
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

EvalResult evaluateSegmented(const StampedTrajectory& gt, const StampedTrajectory& est,
                             const std::vector<EstimateSegment>& segments, const EvalOptions& options,
                             const std::vector<StampedTwist>* twists) {
  if (segments.empty()) throw EvalError("no segments given");
  if (gt.empty()) throw EvalError("the ground truth has no poses");
  // Every estimate pose must belong to a segment: anything else is a pose the estimator never said
  // where it came from.
  std::size_t next = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    while (next < segments.size() && est[i].t_ns > segments[next].t1_ns + kSlackNs) ++next;
    if (next == segments.size() || !inSegment(est[i].t_ns, segments[next])) {
      throw EvalError(fmt::format("estimate pose {} (t = {:.6f} s) lies in no segment", i, nsToSeconds(est[i].t_ns)));
    }
  }

  // Lengths are those of the whole ground truth (rpg's percentages), for every segment alike.
  std::vector<Eigen::Vector3d> gt_positions;
  for (const auto& pose : gt) gt_positions.push_back(pose.p_w_c);
  const double gt_path = distancesFromStart(gt_positions).back();
  EvalOptions segment_options = options;
  if (segment_options.rel_lengths_m.empty()) {
    segment_options.rel_lengths_m = lengthsFromPercentages(gt_path, options.rel_percentages);
    segment_options.rel_lengths_m.erase(
        std::remove_if(segment_options.rel_lengths_m.begin(), segment_options.rel_lengths_m.end(),
                       [](double l) { return !(l > 0.0); }),
        segment_options.rel_lengths_m.end());
  }

  if (segments.size() == 1) {  // one alignment, as evaluate(): the same figures, plus coverage
    EvalResult out = evaluate(gt, est, options);
    if (twists) addVelocityErrors(out, gt, *twists, options);
    SegmentResult r;
    r.index = segments[0].index;
    r.t0_ns = segments[0].t0_ns;
    r.t1_ns = segments[0].t1_ns;
    r.ended_by = segments[0].ended_by;
    r.poses = est.size();
    r.matched = out.matched;
    r.alignment = out.alignment;
    r.ate_rmse_m = out.ate.trans.rmse;
    r.scored = true;
    out.segments = {r};
    out.coverage = coverageOf(segments, gt);
    return out;
  }

  // Each segment on its own, then its poses mapped by its own similarity.
  StampedTrajectory aligned;
  std::vector<SegmentResult> results;
  std::vector<EvalResult> scored;
  std::vector<StampedTwist> scaled_twists;
  std::size_t begin = 0;
  for (const EstimateSegment& s : segments) {
    std::size_t end = begin;
    while (end < est.size() && inSegment(est[end].t_ns, s)) ++end;
    SegmentResult r;
    r.index = s.index;
    r.t0_ns = s.t0_ns;
    r.t1_ns = s.t1_ns;
    r.ended_by = s.ended_by;
    r.poses = end - begin;
    const StampedTrajectory part(est.begin() + static_cast<std::ptrdiff_t>(begin),
                                 est.begin() + static_cast<std::ptrdiff_t>(end));
    begin = end;
    try {
      if (part.empty()) throw EvalError("no pose");
      EvalResult e = evaluate(gt, part, segment_options);
      r.matched = e.matched;
      r.alignment = e.alignment;
      r.ate_rmse_m = e.ate.trans.rmse;
      r.scored = true;
      for (StampedPose p : part) {
        p.p_w_c = e.alignment.apply(p.p_w_c);
        p.q_w_c = Eigen::Quaterniond(e.alignment.rotation * p.q_w_c.toRotationMatrix());
        aligned.push_back(p);
      }
      if (twists) {
        for (StampedTwist t : *twists) {
          if (!inSegment(t.t_ns, s)) continue;
          t.v_c *= e.alignment.scale;  // body-frame twist: only the scale acts on it
          scaled_twists.push_back(t);
        }
      }
      scored.push_back(std::move(e));
    } catch (const EvalError& e) {
      r.note = e.what();
    }
    results.push_back(std::move(r));
  }
  if (scored.empty()) {
    throw EvalError(fmt::format("none of the {} segments could be evaluated (segment {}: {})", segments.size(),
                                results.front().index, results.front().note));
  }

  // Pooled: ATE of the aligned poses; the identity as the combined alignment.
  EvalOptions pooled_options = segment_options;
  pooled_options.align = AlignType::kNone;
  EvalResult out = evaluate(gt, aligned, pooled_options);
  out.align = options.align;
  out.est_poses = est.size();
  out.est_t0_ns = est.front().t_ns;
  out.est_t1_ns = est.back().t_ns;
  out.alignment = Similarity{};
  // Relative errors: sub-trajectories inside one segment (each segment's own, pooled per length).
  out.relative.clear();
  out.matched_gt_path_length_m = 0;
  std::vector<double> all_trans, all_perc, all_rot;
  for (std::size_t k = 0; k < segment_options.rel_lengths_m.size(); ++k) {
    RelativeErrors pooled;
    pooled.length_m = segment_options.rel_lengths_m[k];
    std::size_t pair_offset = 0;
    std::size_t with_samples = 0;
    for (const EvalResult& e : scored) {
      if (k < e.relative.size()) {
        const RelativeErrors& r = e.relative[k];
        pooled.max_dist_diff_m = r.max_dist_diff_m;
        for (std::size_t i : r.start) pooled.start.push_back(i + pair_offset);
        for (std::size_t i : r.end) pooled.end.push_back(i + pair_offset);
        appendAll(pooled.trans_m, r.trans_m);
        appendAll(pooled.trans_perc, r.trans_perc);
        appendAll(pooled.rot_deg, r.rot_deg);
        appendAll(pooled.yaw_deg, r.yaw_deg);
        appendAll(pooled.gravity_deg, r.gravity_deg);
        appendAll(pooled.rot_deg_per_m, r.rot_deg_per_m);
        pooled.shifted_starts += r.shifted_starts;
        with_samples += r.too_few ? 0 : 1;
      }
      pair_offset += e.matched;
    }
    pooled.too_few = with_samples == 0;
    computeRelativeStats(pooled);
    appendAll(all_trans, pooled.trans_m);
    appendAll(all_perc, pooled.trans_perc);
    appendAll(all_rot, pooled.rot_deg);
    out.relative.push_back(std::move(pooled));
  }
  for (const EvalResult& e : scored) out.matched_gt_path_length_m += e.matched_gt_path_length_m;
  out.pooled_trans = computeStats(all_trans);
  out.pooled_trans_perc = computeStats(all_perc);
  out.pooled_rot = computeStats(all_rot);
  // The pair indices above assume the pooled association equals the segments' one after another.
  std::size_t segment_pairs = 0;
  for (const EvalResult& e : scored) segment_pairs += e.matched;
  if (segment_pairs != out.matched) {
    throw EvalError(fmt::format("internal: the segments associate {} poses, the pooled estimate {}",
                                segment_pairs, out.matched));
  }
  if (twists) addVelocityErrors(out, gt, scaled_twists, pooled_options);

  out.coverage = coverageOf(segments, gt);
  for (const SegmentResult& r : results) {
    if (!r.scored) {
      out.warnings.push_back(fmt::format("segment {} ({:.3f}-{:.3f} s, {} poses) not scored: {}", r.index,
                                         nsToSeconds(r.t0_ns), nsToSeconds(r.t1_ns), r.poses, r.note));
    }
  }
  out.segments = std::move(results);
  return out;
}

}  // namespace asynevo::eval
