#pragma once
// Subcommands of the asynevo CLI. Each file registers one subcommand: it parses options and wires
// library calls; the work itself lives in the library modules (DESIGN.md §2: apps stay thin).

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace asynevo::cli {

/// Thrown by a subcommand whose feature is not built yet; main() reports it and exits with
/// kExitNotImplemented.
class NotImplemented : public std::runtime_error {
 public:
  explicit NotImplemented(const std::string& command)
      : std::runtime_error("'asynevo " + command + "' is not implemented yet in this version") {}
};

constexpr int kExitOk = 0;
constexpr int kExitError = 1;            ///< bad input, failed processing
constexpr int kExitNotImplemented = 3;   ///< a registered subcommand that does not exist yet

void addConvertCommand(CLI::App& app);
void addDemoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addTrackCommand(CLI::App& app);
void addSimulateCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addPlotCommand(CLI::App& app);

}  // namespace asynevo::cli
