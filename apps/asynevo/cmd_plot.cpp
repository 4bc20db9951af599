// 'asynevo plot': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addPlotCommand(CLI::App& app) {
  static std::string run;
  auto* cmd = app.add_subcommand("plot", "Draw figures for a run folder");
  cmd->add_option("--run", run, "run folder")->required();
  cmd->callback([] { throw NotImplemented("plot"); });
}

}  // namespace asynevo::cli
