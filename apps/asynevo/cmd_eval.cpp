// 'asynevo eval': evaluate an estimated trajectory against ground truth (DESIGN.md §1, §6) with
// rpg_trajectory_evaluation's definitions, plus the body-velocity error when the estimate's twists are
// known; writes DIR/eval.json and rpg-style YAML files.
#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/eval/evaluate.hpp"
#include "asynevo/eval/report.hpp"
#include "asynevo/eval/segments.hpp"
#include "asynevo/eval/timing.hpp"
#include "commands.hpp"
#include "sensor_option.hpp"

namespace asynevo::cli {

void addEvalCommand(CLI::App& app) {
  static std::string gt, gt_topic, est, align = "sim3", out, velocities, segments;
  static int align_frames = -1;
  static std::vector<double> rel_lengths;
  auto* cmd = app.add_subcommand("eval", "Evaluate an estimated trajectory against ground truth");
  cmd->add_option("--gt", gt, "ground-truth trajectory (TUM: t tx ty tz qx qy qz qw, or a ROS bag with a pose topic)")
      ->required();
  addGtTopicOption(cmd, gt_topic);
  cmd->add_option("--est", est, "estimated trajectory (TUM)")->required();
  cmd->add_option("--align", align, "alignment (sim3, se3, posyaw, none)")
      ->check(CLI::IsMember({"sim3", "se3", "posyaw", "none"}));
  cmd->add_option("--align-frames", align_frames, "poses used for the alignment (-1 = all)");
  cmd->add_option("--rel-lengths", rel_lengths,
                  "relative-error sub-trajectory lengths in metres (default: 10,20,30,40,50 % of the "
                  "ground-truth path length)")
      ->delimiter(',');
  cmd->add_option("--velocities", velocities,
                  "estimated body-frame twists (t vx vy vz wx wy wz) for the velocity error (default: "
                  "velocities.txt beside --est when it exists; 'none' skips it)");
  cmd->add_option("--segments", segments,
                  "the run's segments.txt: each segment aligned on its own, errors pooled, coverage reported "
                  "(default: segments.txt beside --est when it exists; 'none' evaluates the estimate as one piece)");
  cmd->add_option("--out", out, "folder for eval.json")->required();
  cmd->callback([] {
    eval::EvalOptions options;
    options.align = *eval::parseAlignType(align);
    options.align_frames = align_frames;
    options.gt_topic = gt_topic;
    options.rel_lengths_m = rel_lengths;
    const std::string twists = velocities == "none" ? std::string()
                               : velocities.empty() ? eval::velocitiesBesideEstimate(est)
                                                    : velocities;
    const std::string segments_file = segments == "none" ? std::string()
                                      : segments.empty() ? eval::segmentsBesideEstimate(est)
                                                         : segments;
    const eval::EvalResult result = eval::evaluateFiles(gt, est, options, twists, segments_file);

    // A run folder's timing.csv, if the output folder is one.
    std::optional<eval::TimingStats> timing;
    const std::string timing_path = (std::filesystem::path(out) / "timing.csv").string();
    if (std::filesystem::exists(timing_path)) {
      try {
        timing = eval::readTimingStats(timing_path);
      } catch (const InputError& e) {
        fmt::print(stderr, "warning: timing statistics skipped: {}\n", e.what());
      }
    }
    eval::ReportInputs inputs{gt, est, timing ? &*timing : nullptr};
    const auto written = eval::writeEvalOutputs(out, result, inputs);
    fmt::print("{}", eval::summaryTable(result, timing ? &*timing : nullptr));
    fmt::print("wrote {}\n", written.front());
  });
}

}  // namespace asynevo::cli
