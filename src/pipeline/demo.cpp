#include "asynevo/pipeline/demo.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/eval/plot.hpp"
#include "asynevo/eval/report.hpp"
#include "asynevo/eval/segments.hpp"
#include "asynevo/eval/timing.hpp"

namespace asynevo::pipeline {

DemoResult runDemo(const DemoOptions& options,
                   const std::function<void(int64_t t_ns, uint64_t events)>& simulation_progress,
                   const std::function<void(const PipelineProgress&)>& run_progress) {
  namespace fs = std::filesystem;
  DemoResult result;
  result.sequence_dir = (fs::path(options.out) / "sequence").string();
  result.run_dir = (fs::path(options.out) / "run").string();

  sim::SimulationSpec spec;
  spec.scene = options.scene;
  spec.motion = options.motion;
  spec.duration_s = options.duration_s;
  spec.seed = options.seed;
  const auto sim_start = std::chrono::steady_clock::now();
  result.simulation = sim::simulateToFolder(spec, result.sequence_dir, simulation_progress);
  result.simulation_wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sim_start).count();

  RunOptions run;
  run.dataset = result.sequence_dir;
  run.out = result.run_dir;
  run.config = Config();  // the defaults are tuned for the DAVIS240C-like simulated camera (config/sim.yaml)
  result.run = runDataset(run, run_progress);
  if (!result.run.initialized()) {
    result.evaluation_error = initializationFailureMessage(result.run);
    return result;
  }

  const fs::path dir(result.run_dir);
  const std::string gt = (dir / "stamped_groundtruth.txt").string(),
                    est = (dir / "stamped_traj_estimate.txt").string();
  try {
    result.evaluation = eval::evaluateFiles(gt, est, eval::EvalOptions{}, eval::velocitiesBesideEstimate(est),
                                             eval::segmentsBesideEstimate(est));
    const eval::TimingStats timing = eval::readTimingStats((dir / "timing.csv").string());
    eval::writeEvalOutputs(result.run_dir, *result.evaluation, {gt, est, &timing});
  } catch (const Error& e) {
    result.evaluation.reset();
    result.evaluation_error = e.what();
  }
  if (options.plots) {
    try {
      result.plot_status = eval::runPlotScript(result.run_dir);
    } catch (const Error& e) {
      result.plot_error = e.what();
    }
  }
  return result;
}

std::string demoReportText(const DemoResult& r) {
  std::string t;
  const auto& s = r.simulation;
  t += fmt::format("sequence        {} | {}, {:.1f} s, {} events (simulated in {:.1f} s)\n",
                   s.scene_description, s.motion_description, durationSeconds(s.begin_ns, s.end_ns),
                   s.stats.events, r.simulation_wall_s);
  t += runSummaryText(r.run);
  if (r.evaluation) {
    const eval::EvalResult& e = *r.evaluation;
    const double path = e.gt_path_length_m;
    t += fmt::format("accuracy        Sim(3) alignment (scale {:.4f}), {} poses matched, path {:.3f} m\n",
                     e.alignment.scale, e.matched, path);
    t += fmt::format("  ATE           RMSE {:.4f} m ({:.2f} % of the path), rotation RMSE {:.2f} deg\n",
                     e.ate.trans.rmse, path > 0 ? 100.0 * e.ate.trans.rmse / path : 0.0, e.ate.rot.rmse);
    for (const eval::RelativeErrors& rel : e.relative) {
      if (rel.too_few) continue;
      t +=
          fmt::format("  RTE {:5.2f} m   mean translation error {:.2f} %, rotation {:.2f} deg ({} samples)\n",
                      rel.length_m, rel.trans_perc_stats.mean, rel.rot.mean, rel.trans_m.size());
    }
    if (e.velocity && e.velocity->samples > 0)
      t += fmt::format("  velocity      RMSE {:.4f} m/s ({:.1f} % of the mean speed {:.3f} m/s), angular {:.2f} deg/s\n",
                       e.velocity->linear_mps.rmse, e.velocity->linear_rmse_perc, e.velocity->mean_gt_speed_mps,
                       e.velocity->angular_dps.rmse);
    if (e.velocity && e.velocity->direction_deg.num_samples > 0)
      t += fmt::format("  direction     median {:.1f} deg from the true direction of travel, {:.1f} % of the knots in reverse\n",
                       e.velocity->direction_deg.median, 100.0 * e.velocity->reversed_fraction);
  } else {
    t += "accuracy        not evaluated: " + r.evaluation_error + "\n";
  }
  t += fmt::format("real-time factor {:.2f} (wall time / sequence duration; < 1 is faster than real time)\n",
                   r.run.pipeline.realTimeFactor());
  if (r.plot_status == 0)
    t += fmt::format("figures         {}\n", (std::filesystem::path(r.run_dir) / "plots").string());
  else if (!r.plot_error.empty())
    t += "figures         skipped: " + r.plot_error + "\n";
  else if (r.plot_status > 0)
    t += fmt::format("figures         plot_run.py failed (exit status {})\n", r.plot_status);
  t += fmt::format("wrote           {} (sequence/ = simulated data, run/ = run folder with eval.json)\n",
                   std::filesystem::absolute(std::filesystem::path(r.run_dir).parent_path()).string());
  return t;
}

}  // namespace asynevo::pipeline
