// 'asynevo plot': figures for a run folder (DESIGN.md §1), drawn by tools/plot_run.py with
// matplotlib. If the folder has both trajectories but no eval.json yet, it is evaluated first (with
// the defaults of 'asynevo eval') so the figures can show the aligned estimate and relative errors.
#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/eval/evaluate.hpp"
#include "asynevo/eval/plot.hpp"
#include "asynevo/eval/report.hpp"
#include "asynevo/eval/segments.hpp"
#include "asynevo/eval/timing.hpp"
#include "commands.hpp"

namespace asynevo::cli {

void addPlotCommand(CLI::App& app) {
  static std::string run;
  auto* cmd = app.add_subcommand("plot", "Draw figures for a run folder");
  cmd->add_option("--run", run, "run folder")->required();
  cmd->callback([] {
    namespace fs = std::filesystem;
    if (!fs::is_directory(run)) throw InputError(run, "not a folder");
    const fs::path dir(run);
    const fs::path gt = dir / "stamped_groundtruth.txt", est = dir / "stamped_traj_estimate.txt";
    if (!fs::exists(dir / "eval.json") && fs::exists(gt) && fs::exists(est)) {
      try {
        const eval::EvalResult result = eval::evaluateFiles(gt.string(), est.string(), eval::EvalOptions{},
                                                                  eval::velocitiesBesideEstimate(est.string()),
                                                                  eval::segmentsBesideEstimate(est.string()));
        std::optional<eval::TimingStats> timing;
        if (fs::exists(dir / "timing.csv")) timing = eval::readTimingStats((dir / "timing.csv").string());
        eval::writeEvalOutputs(run, result, {gt.string(), est.string(), timing ? &*timing : nullptr});
        fmt::print("evaluated the run first (sim3, all frames): {}\n", (dir / "eval.json").string());
      } catch (const Error& e) {
        fmt::print(stderr, "warning: evaluation skipped ({}); figures that need it are skipped too\n",
                   e.what());
      }
    }
    const int status = eval::runPlotScript(run);
    if (status != 0) throw Error(fmt::format("plot_run.py failed (exit status {})", status));
  });
}

}  // namespace asynevo::cli
