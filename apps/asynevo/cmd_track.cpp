// 'asynevo track': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addTrackCommand(CLI::App& app) {
  static std::string dataset, out;
  auto* cmd = app.add_subcommand("track", "Run the frontend only and write feature tracks");
  cmd->add_option("--dataset", dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--out", out, "tracks file (id t x y)")->required();
  cmd->callback([] { throw NotImplemented("track"); });
}

}  // namespace asynevo::cli
