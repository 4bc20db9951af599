#pragma once
// 'asynevo demo' (DESIGN.md §1): simulate a built-in ~10 s 6-DoF sequence, run AsynEVO on it, evaluate
// the estimate against the exact ground truth (Sim(3), rpg_trajectory_evaluation definitions) and
// draw the figures. Needs nothing but the built binary (and python3-matplotlib for the figures).
//
//   <out>/sequence/   the simulated ECD-format folder (events.txt, groundtruth.txt, calib.txt, ...)
//   <out>/run/        the run folder (docs/pipeline.md) plus eval.json and plots/

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "asynevo/eval/evaluate.hpp"
#include "asynevo/pipeline/run.hpp"
#include "asynevo/sim/simulate.hpp"

namespace asynevo::pipeline {

struct DemoOptions {
  std::string out = "asynevo_demo";
  std::string scene = "boxes";  ///< textured cubes before a wall: many corners, depth variation
  std::string motion = "6dof";
  double duration_s = 10.0;
  uint64_t seed = 1;
  bool plots = true;
};

struct DemoResult {
  std::string sequence_dir, run_dir;
  sim::SimulationResult simulation;
  double simulation_wall_s = 0;
  RunSummary run;
  std::optional<eval::EvalResult> evaluation;  ///< unset when the run did not initialize
  std::string evaluation_error;
  int plot_status = -1;  ///< plot_run.py's exit status; -1 = not run
  std::string plot_error;
};

/// Runs the whole demo. Throws like simulateToFolder / runDataset; a failed evaluation or plot is
/// reported in the result instead.
DemoResult runDemo(const DemoOptions& options,
                   const std::function<void(int64_t t_ns, uint64_t events)>& simulation_progress = {},
                   const std::function<void(const PipelineProgress&)>& run_progress = {});

/// The demo's report for the terminal: sequence, accuracy (ATE, relative error), speed, where it wrote.
std::string demoReportText(const DemoResult& result);

}  // namespace asynevo::pipeline
