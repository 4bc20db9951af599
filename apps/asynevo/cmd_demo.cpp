// 'asynevo demo [--out DIR]' (DESIGN.md §1): simulate a built-in ~10 s 6-DoF sequence, run AsynEVO,
// evaluate (Sim(3)), print ATE/RTE and the real-time factor, write figures. The work is
// pipeline::runDemo (docs/pipeline.md §Demo); this file parses, shows progress and reports.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>

#include "allocator.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/pipeline/demo.hpp"
#include "commands.hpp"
#include "progress.hpp"

namespace asynevo::cli {

void addDemoCommand(CLI::App& app) {
  auto options = std::make_shared<pipeline::DemoOptions>();
  auto no_plots = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("demo", "Simulate a short sequence, run AsynEVO on it, evaluate, report");
  cmd->add_option("--out", options->out, "output folder")->capture_default_str();
  cmd->add_option("--scene", options->scene, "built-in scene to simulate")->capture_default_str();
  cmd->add_option("--motion", options->motion, "motion preset")->capture_default_str();
  cmd->add_option("--duration", options->duration_s, "seconds to simulate")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", options->seed, "random seed of the simulation")->capture_default_str();
  cmd->add_flag("--no-plots", *no_plots, "skip the figures (python3-matplotlib)");
  cmd->callback([options, no_plots] {
    options->plots = !*no_plots;
    fmt::print("asynevo demo: simulating {} s of '{}' with '{}' motion into {}\n", options->duration_s,
               options->scene, options->motion,
               std::filesystem::absolute(std::filesystem::path(options->out) / "sequence").string());
    std::fflush(stdout);
    auto sim_progress = std::make_unique<Progress>();
    int64_t sim_first = -1;
    std::unique_ptr<Progress> run_progress;
    useOneAllocatorArena();  // before the demo's threads: flat memory over long runs
    const pipeline::DemoResult result = pipeline::runDemo(
        *options,
        [&](int64_t t_ns, uint64_t events) {
          if (sim_first < 0) sim_first = t_ns;
          sim_progress->update(events, t_ns, sim_first);
        },
        [&](const pipeline::PipelineProgress& p) {
          if (!run_progress) {
            sim_progress.reset();
            run_progress = std::make_unique<Progress>();
          }
          run_progress->update(p.events, p.event_t_ns, p.first_t_ns);
        });
    sim_progress.reset();
    run_progress.reset();
    fmt::print("{}", pipeline::demoReportText(result));
    if (!result.run.initialized()) throw Error(pipeline::initializationFailureMessage(result.run));
  });
}

}  // namespace asynevo::cli
