#include "asynevo/eval/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/core/json.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::eval {

namespace {

std::string num(double v) { return jsonNumber(v); }
std::string quoted(const std::string& s) { return jsonQuoted(s); }

std::string array(const std::vector<double>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out += ", ";
    out += num(values[i]);
  }
  return out + "]";
}

std::string statsJson(const Stats& s) {
  if (s.num_samples == 0) return "{\"num_samples\": 0}";
  return fmt::format(
      "{{\"rmse\": {}, \"mean\": {}, \"median\": {}, \"std\": {}, \"min\": {}, \"max\": {}, \"num_samples\": "
      "{}}}",
      num(s.rmse), num(s.mean), num(s.median), num(s.std), num(s.min), num(s.max), s.num_samples);
}

std::string columnJson(const ColumnStats& c) {
  return fmt::format("{{\"name\": {}, \"mean\": {}, \"median\": {}, \"p95\": {}, \"max\": {}, \"sum\": {}}}",
                     quoted(c.name), num(c.mean), num(c.median), num(c.p95), num(c.max), num(c.sum));
}

/// rpg's YAML block for one statistic (yaml.dump sorts the keys).
std::string statsYaml(const std::string& label, const Stats& s) {
  if (s.num_samples == 0) return fmt::format("{}:\n  num_samples: 0\n", label);
  return fmt::format(
      "{}:\n  max: {}\n  mean: {}\n  median: {}\n  min: {}\n  num_samples: {}\n  rmse: {}\n  std: {}\n",
      label, num(s.max), num(s.mean), num(s.median), num(s.min), s.num_samples, num(s.rmse), num(s.std));
}

void writeFile(const std::string& path, const std::string& content) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw Error(fmt::format("{}: cannot open file for writing", path));
  const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  if (std::fclose(f) != 0 || !ok) throw Error(fmt::format("{}: write failed", path));
}

std::string formatStatsRow(const char* name, const Stats& s, double factor, const char* unit) {
  if (s.num_samples == 0) return fmt::format("  {:<18} (no samples)\n", name);
  return fmt::format("  {:<18} rmse {:9.4f}  mean {:9.4f}  median {:9.4f}  max {:9.4f} {}\n", name,
                     s.rmse * factor, s.mean * factor, s.median * factor, s.max * factor, unit);
}

}  // namespace

std::string evalJson(const EvalResult& r, const ReportInputs& inputs) {
  std::string j = "{\n";
  j += fmt::format("  \"gt_file\": {},\n  \"est_file\": {},\n", quoted(inputs.gt_path),
                   quoted(inputs.est_path));
  j += "  \"reference\": \"rpg_trajectory_evaluation definitions (docs/evaluation.md)\",\n";
  j += fmt::format(
      "  \"association\": {{\"max_time_diff_s\": {}, \"gt_poses\": {}, \"est_poses\": {}, \"matched\": {}, "
      "\"gt_time_s\": [{}, {}], \"est_time_s\": [{}, {}]}},\n",
      num(nsToSeconds(r.max_time_diff_ns)), r.gt_poses, r.est_poses, r.matched, num(nsToSeconds(r.gt_t0_ns)),
      num(nsToSeconds(r.gt_t1_ns)), num(nsToSeconds(r.est_t0_ns)), num(nsToSeconds(r.est_t1_ns)));
  const auto& R = r.alignment.rotation;
  j += fmt::format(
      "  \"alignment\": {{\"type\": {}, \"num_frames\": {}, \"scale\": {}, \"rotation\": [[{}, {}, {}], [{}, "
      "{}, {}], "
      "[{}, {}, {}]], \"translation\": [{}, {}, {}]}},\n",
      quoted(alignTypeName(r.align)), r.align_frames, num(r.alignment.scale), num(R(0, 0)), num(R(0, 1)),
      num(R(0, 2)), num(R(1, 0)), num(R(1, 1)), num(R(1, 2)), num(R(2, 0)), num(R(2, 1)), num(R(2, 2)),
      num(r.alignment.translation.x()), num(r.alignment.translation.y()), num(r.alignment.translation.z()));
  if (r.coverage) {
    j += fmt::format("  \"coverage\": {},\n  \"segments\": [", num(*r.coverage));
    for (std::size_t k = 0; k < r.segments.size(); ++k) {
      const SegmentResult& g = r.segments[k];
      j += fmt::format(
          "{}\n    {{\"index\": {}, \"start_s\": {}, \"end_s\": {}, \"ended_by\": {}, \"poses\": {}, "
          "\"matched\": {}, \"scored\": {}, \"scale\": {}, \"ate_rmse_m\": {}, \"note\": {}}}",
          k ? "," : "", g.index, num(nsToSeconds(g.t0_ns)), num(nsToSeconds(g.t1_ns)), quoted(g.ended_by), g.poses,
          g.matched, g.scored ? "true" : "false", num(g.alignment.scale), num(g.ate_rmse_m), quoted(g.note));
    }
    j += r.segments.empty() ? "],\n" : "\n  ],\n";
  }
  j += fmt::format("  \"gt_path_length_m\": {},\n  \"matched_gt_path_length_m\": {},\n",
                   num(r.gt_path_length_m), num(r.matched_gt_path_length_m));
  j += fmt::format(
      "  \"ate\": {{\n    \"trans_m\": {},\n    \"rot_deg\": {},\n    \"scale_perc\": {}\n  }},\n",
      statsJson(r.ate.trans), statsJson(r.ate.rot), statsJson(r.ate.scale));
  j += "  \"relative_error\": {\n    \"per_length\": [";
  for (std::size_t k = 0; k < r.relative.size(); ++k) {
    const RelativeErrors& e = r.relative[k];
    std::vector<double> t_start;
    for (std::size_t i : e.start) t_start.push_back(nsToSeconds(r.pairs.t_gt_ns[i]));
    j += k ? ",\n      {" : "\n      {";
    j += fmt::format(
        "\"length_m\": {}, \"max_dist_diff_m\": {}, \"num_samples\": {}, \"too_few\": {}, "
        "\"shifted_starts\": {},\n"
        "       \"trans_m\": {},\n       \"trans_perc\": {},\n       \"rot_deg\": {},\n       \"yaw_deg\": "
        "{},\n"
        "       \"gravity_deg\": {},\n       \"rot_deg_per_m\": {},\n"
        "       \"samples\": {{\"t_start_s\": {}, \"trans_m\": {}, \"trans_perc\": {}, \"rot_deg\": {}}}}}",
        num(e.length_m), num(e.max_dist_diff_m), e.trans_m.size(), e.too_few ? "true" : "false",
        e.shifted_starts, statsJson(e.trans), statsJson(e.trans_perc_stats), statsJson(e.rot),
        statsJson(e.yaw), statsJson(e.gravity), statsJson(e.rot_per_m), array(t_start), array(e.trans_m),
        array(e.trans_perc), array(e.rot_deg));
  }
  j += r.relative.empty() ? "],\n" : "\n    ],\n";
  j += fmt::format("    \"pooled\": {{\"trans_m\": {}, \"trans_perc\": {}, \"rot_deg\": {}}}\n  }},\n",
                   statsJson(r.pooled_trans), statsJson(r.pooled_trans_perc), statsJson(r.pooled_rot));
  if (r.velocity) {
    const VelocityErrors& v = *r.velocity;
    j += fmt::format(
        "  \"velocity\": {{\"file\": {}, \"definition\": {},\n    \"scale_applied\": {}, \"est_twists\": {}, "
        "\"samples\": {},\n    \"linear_mps\": {},\n    \"angular_dps\": {},\n    \"mean_gt_speed_mps\": {}, "
        "\"mean_gt_rate_dps\": {}, \"linear_rmse_perc_of_mean_speed\": {}, "
        "\"angular_rmse_perc_of_mean_rate\": {},\n    \"direction_deg\": {},\n    \"reversed_fraction\": {}}},\n",
        quoted(r.velocities_path),
        quoted("body-frame twist; linear part times the alignment scale vs R_gt^T dp_gt/dt (central "
               "differences of the ground-truth poses, interpolated at the twist times; docs/evaluation.md)"),
        num(v.scale), v.est_twists, v.samples, statsJson(v.linear_mps), statsJson(v.angular_dps),
        num(v.mean_gt_speed_mps), num(v.mean_gt_rate_dps), num(v.linear_rmse_perc), num(v.angular_rmse_perc),
        statsJson(v.direction_deg), num(v.reversed_fraction));
  }
  if (inputs.timing) {
    const TimingStats& t = *inputs.timing;
    j += fmt::format(
        "  \"timing\": {{\"updates\": {}, \"t_first_s\": {}, \"t_last_s\": {}, \"total_ms_sum\": {}, "
        "\"backend_real_time_factor\": {},\n    \"stages\": [",
        t.updates, num(t.t_first_s), num(t.t_last_s), num(t.total_ms_sum), num(t.backend_real_time_factor));
    for (std::size_t k = 0; k < t.stages.size(); ++k) j += (k ? ", " : "") + columnJson(t.stages[k]);
    j += "],\n    \"other_columns\": [";
    for (std::size_t k = 0; k < t.others.size(); ++k) j += (k ? ", " : "") + columnJson(t.others[k]);
    j += "]},\n";
  }
  j += "  \"warnings\": [";
  for (std::size_t k = 0; k < r.warnings.size(); ++k) j += (k ? ", " : "") + quoted(r.warnings[k]);
  j += "]\n}\n";
  return j;
}

std::vector<std::string> writeEvalOutputs(const std::string& dir, const EvalResult& r,
                                          const ReportInputs& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(fmt::format("{}: cannot create folder: {}", dir, ec.message()));
  std::vector<std::string> written;
  const std::string json_path = (fs::path(dir) / "eval.json").string();
  writeFile(json_path, evalJson(r, inputs));
  written.push_back(json_path);

  // rpg: absolute_err_statistics_<align_type>_<align_num_frames>.yaml with trans, rot, scale.
  const std::string abs_path = (fs::path(dir) / fmt::format("absolute_err_statistics_{}_{}.yaml",
                                                            alignTypeName(r.align), r.align_frames))
                                   .string();
  writeFile(abs_path,
            statsYaml("rot", r.ate.rot) + statsYaml("scale", r.ate.scale) + statsYaml("trans", r.ate.trans));
  written.push_back(abs_path);

  // rpg: relative_error_statistics_<"{:3.1f}" of the length, '.' → '_'>.yaml.
  for (const RelativeErrors& e : r.relative) {
    std::string name = fmt::format("{:3.1f}", e.length_m);
    for (char& c : name) {
      if (c == '.') c = '_';
    }
    const std::string path =
        (fs::path(dir) / fmt::format("relative_error_statistics_{}.yaml", name)).string();
    writeFile(path, statsYaml("gravity", e.gravity) + statsYaml("rot", e.rot) + statsYaml("trans", e.trans) +
                        statsYaml("trans_perc", e.trans_perc_stats) + statsYaml("yaw", e.yaw));
    written.push_back(path);
  }
  return written;
}

std::string summaryTable(const EvalResult& r, const TimingStats* timing) {
  std::string s;
  s += fmt::format("associated {} of {} estimate poses with {} ground-truth poses (|dt| < {} s)\n", r.matched,
                   r.est_poses, r.gt_poses, nsToSeconds(r.max_time_diff_ns));
  if (r.segments.size() > 1) {
    s += fmt::format("alignment {} ({} frames) per segment; {} segments cover {:.1f} % of the ground truth:\n",
                     alignTypeName(r.align), r.align_frames < 0 ? std::string("all") : std::to_string(r.align_frames),
                     r.segments.size(), 100.0 * r.coverage.value_or(0.0));
    for (const SegmentResult& g : r.segments) {
      s += g.scored ? fmt::format("  segment {}: {:.3f}-{:.3f} s, {} poses, scale {:.6f}, ATE {:.4f} m, ended by {}\n",
                                  g.index, nsToSeconds(g.t0_ns), nsToSeconds(g.t1_ns), g.poses, g.alignment.scale,
                                  g.ate_rmse_m, g.ended_by)
                    : fmt::format("  segment {}: {:.3f}-{:.3f} s, {} poses, not scored ({}), ended by {}\n", g.index,
                                  nsToSeconds(g.t0_ns), nsToSeconds(g.t1_ns), g.poses, g.note, g.ended_by);
    }
  } else {
    s += fmt::format("alignment {} ({} frames): scale {:.6f}\n", alignTypeName(r.align),
                     r.align_frames < 0 ? std::string("all") : std::to_string(r.align_frames), r.alignment.scale);
    if (r.coverage) s += fmt::format("one segment, covering {:.1f} % of the ground truth\n", 100.0 * *r.coverage);
  }
  s += fmt::format("ground-truth path {:.3f} m (associated part {:.3f} m)\n", r.gt_path_length_m,
                   r.matched_gt_path_length_m);
  s += "absolute trajectory error (ATE):\n";
  s += formatStatsRow("translation", r.ate.trans, 1.0, "m");
  s += formatStatsRow("rotation", r.ate.rot, 1.0, "deg");
  s += "relative error:\n";
  s += fmt::format("  {:>9} {:>8} {:>11} {:>11} {:>10} {:>9}\n", "length m", "samples", "trans rmse",
                   "trans med", "trans% avg", "rot° avg");
  for (const RelativeErrors& e : r.relative) {
    if (e.trans.num_samples == 0) {
      s += fmt::format("  {:9.2f} {:>8} (too few sub-trajectories)\n", e.length_m, 0);
      continue;
    }
    s += fmt::format("  {:9.2f} {:8} {:11.4f} {:11.4f} {:10.3f} {:9.3f}\n", e.length_m, e.trans.num_samples,
                     e.trans.rmse, e.trans.median, e.trans_perc_stats.mean, e.rot.mean);
  }
  if (r.pooled_trans.num_samples > 0) {
    s +=
        fmt::format("  {:>9} {:8} {:11.4f} {:11.4f} {:10.3f} {:9.3f}\n", "pooled", r.pooled_trans.num_samples,
                    r.pooled_trans.rmse, r.pooled_trans.median, r.pooled_trans_perc.mean, r.pooled_rot.mean);
  }
  if (r.velocity && r.velocity->samples > 0) {
    const VelocityErrors& v = *r.velocity;
    s += fmt::format("body velocity ({} of {} twists; linear part times the scale {:.6f}):\n", v.samples,
                     v.est_twists, v.scale);
    s += formatStatsRow("linear", v.linear_mps, 1.0, "m/s");
    s += formatStatsRow("angular", v.angular_dps, 1.0, "deg/s");
    s += fmt::format(
        "  {:<18} linear {:.2f} % of the mean ground-truth speed ({:.4f} m/s), angular {:.2f} % of "
        "the mean rate ({:.3f} deg/s)\n",
        "rmse / mean", v.linear_rmse_perc, v.mean_gt_speed_mps, v.angular_rmse_perc, v.mean_gt_rate_dps);
    if (v.direction_deg.num_samples > 0) {
      s += fmt::format(
          "  {:<18} median {:.1f} deg from the ground truth's; in reverse (> 90 deg) {:.1f} % of {} twists{}\n",
          "direction", v.direction_deg.median, 100.0 * v.reversed_fraction, v.direction_deg.num_samples,
          v.reversed_fraction > 0.5 ? ": the estimate travels backwards" : "");
    }
  }
  if (timing) {
    s += fmt::format("backend: {} updates", timing->updates);
    if (timing->has_total) {
      for (const ColumnStats& c : timing->stages) {
        if (c.name == "total_ms") {
          s += fmt::format(", total per update mean {:.2f} ms, p95 {:.2f} ms, max {:.2f} ms", c.mean, c.p95,
                           c.max);
        }
      }
      s += fmt::format(", backend real-time factor {:.3f}", timing->backend_real_time_factor);
    }
    s += "\n";
  }
  for (const std::string& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

}  // namespace asynevo::eval
