// 'asynevo run': contract fixed by DESIGN.md §1; the implementation has not landed yet.
#include <string>

#include "commands.hpp"

namespace asynevo::cli {

void addRunCommand(CLI::App& app) {
  static std::string dataset, format = "auto", calib, config, backend = "window", out;
  auto* cmd = app.add_subcommand("run", "Estimate the camera trajectory of a dataset");
  cmd->add_option("--dataset", dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--format", format, "input format (auto, ecd, mvsec, aevt)");
  cmd->add_option("--calib", calib, "calibration file (ECD calib.txt or Kalibr YAML)");
  cmd->add_option("--config", config, "configuration YAML (overrides the defaults)");
  cmd->add_option("--backend", backend, "estimator (window, incremental)");
  cmd->add_option("--out", out, "run folder to write")->required();
  cmd->callback([] { throw NotImplemented("run"); });
}

}  // namespace asynevo::cli
