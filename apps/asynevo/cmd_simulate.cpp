// 'asynevo simulate': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addSimulateCommand(CLI::App& app) {
  static std::string scene, motion, out;
  static double duration = 0;
  static unsigned seed = 0;
  auto* cmd = app.add_subcommand("simulate", "Simulate an event camera with exact ground truth");
  cmd->add_option("--scene", scene, "built-in scene name or scene file")->required();
  cmd->add_option("--motion", motion, "motion preset or TUM/ECD ground-truth file")->required();
  cmd->add_option("--duration", duration, "seconds to simulate");
  cmd->add_option("--seed", seed, "random seed");
  cmd->add_option("--out", out, "output folder (ECD layout)")->required();
  cmd->callback([] { throw NotImplemented("simulate"); });
}

}  // namespace asynevo::cli
