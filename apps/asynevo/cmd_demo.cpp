// 'asynevo demo': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addDemoCommand(CLI::App& app) {
  static std::string out;
  auto* cmd = app.add_subcommand("demo", "Simulate a short sequence, run AsynEVO on it, evaluate, report");
  cmd->add_option("--out", out, "output folder");
  cmd->callback([] { throw NotImplemented("demo"); });
}

}  // namespace asynevo::cli
