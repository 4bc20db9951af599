// Subcommands whose contract (name and flags, DESIGN.md §1) is fixed but whose implementation has not
// landed yet. Each moves to a file of its own when it is implemented.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

namespace {

struct PendingOptions {
  std::string dataset, format = "auto", calib, config, backend = "window", out, scene, motion, gt, est,
      align = "sim3", run;
  double duration = 0;
  unsigned seed = 0;
  int align_frames = -1;
};

PendingOptions& options() {
  static PendingOptions storage;  // CLI11 binds to stable addresses; one parse per process
  return storage;
}

}  // namespace

void addDemoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("demo", "Simulate a short sequence, run AsynEVO on it, evaluate, report");
  cmd->add_option("--out", options().out, "output folder (default: a new folder under the current one)");
  cmd->callback([] { throw NotImplemented("demo"); });
}

void addRunCommand(CLI::App& app) {
  auto& o = options();
  auto* cmd = app.add_subcommand("run", "Estimate the camera trajectory of a dataset");
  cmd->add_option("--dataset", o.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--format", o.format, "input format")->check(CLI::IsMember({"auto", "ecd", "mvsec", "aevt"}));
  cmd->add_option("--calib", o.calib, "calibration file (ECD calib.txt or Kalibr YAML)");
  cmd->add_option("--config", o.config, "configuration YAML (overrides the defaults)");
  cmd->add_option("--backend", o.backend, "estimator")->check(CLI::IsMember({"window", "incremental"}));
  cmd->add_option("--out", o.out, "run folder to write")->required();
  cmd->callback([] { throw NotImplemented("run"); });
}

void addTrackCommand(CLI::App& app) {
  auto& o = options();
  auto* cmd = app.add_subcommand("track", "Run the frontend only and write feature tracks");
  cmd->add_option("--dataset", o.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--out", o.out, "tracks file (id t x y)")->required();
  cmd->callback([] { throw NotImplemented("track"); });
}

void addSimulateCommand(CLI::App& app) {
  auto& o = options();
  auto* cmd = app.add_subcommand("simulate", "Simulate an event camera with exact ground truth");
  cmd->add_option("--scene", o.scene, "built-in scene name or scene file")->required();
  cmd->add_option("--motion", o.motion, "motion preset or TUM/ECD ground-truth file")->required();
  cmd->add_option("--duration", o.duration, "seconds to simulate");
  cmd->add_option("--seed", o.seed, "random seed");
  cmd->add_option("--out", o.out, "output folder (ECD layout)")->required();
  cmd->callback([] { throw NotImplemented("simulate"); });
}

void addEvalCommand(CLI::App& app) {
  auto& o = options();
  auto* cmd = app.add_subcommand("eval", "Evaluate an estimated trajectory against ground truth");
  cmd->add_option("--gt", o.gt, "ground-truth trajectory (TUM)")->required();
  cmd->add_option("--est", o.est, "estimated trajectory (TUM)")->required();
  cmd->add_option("--align", o.align, "alignment")->check(CLI::IsMember({"sim3", "se3", "posyaw", "none"}));
  cmd->add_option("--align-frames", o.align_frames, "poses used for the alignment (-1 = all)");
  cmd->add_option("--out", o.out, "folder for eval.json")->required();
  cmd->callback([] { throw NotImplemented("eval"); });
}

void addPlotCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Draw figures for a run folder");
  cmd->add_option("--run", options().run, "run folder")->required();
  cmd->callback([] { throw NotImplemented("plot"); });
}

}  // namespace asynevo::cli
