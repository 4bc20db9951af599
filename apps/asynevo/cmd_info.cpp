#include "commands.hpp"

namespace asynevo::cli {
void addInfoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Describe a dataset");
  static std::string dataset;
  cmd->add_option("--dataset", dataset, "ECD-style folder or event file")->required();
  cmd->callback([] { throw NotImplemented("info"); });
}
}  // namespace asynevo::cli
