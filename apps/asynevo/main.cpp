// asynevo: one binary, one subcommand per task (DESIGN.md §1).
#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "asynevo/core/error.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"AsynEVO: asynchronous event-driven visual odometry for pure event streams"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "asynevo 0.1.0");
  asynevo::cli::addDemoCommand(app);
  asynevo::cli::addInfoCommand(app);
  asynevo::cli::addRunCommand(app);
  asynevo::cli::addTrackCommand(app);
  asynevo::cli::addSimulateCommand(app);
  asynevo::cli::addEvalCommand(app);
  asynevo::cli::addPlotCommand(app);
  asynevo::cli::addConvertCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const asynevo::cli::NotImplemented& e) {
    fmt::print(stderr, "asynevo: {}\n", e.what());
    return asynevo::cli::kExitNotImplemented;
  } catch (const asynevo::Error& e) {
    fmt::print(stderr, "asynevo: error: {}\n", e.what());
    return asynevo::cli::kExitError;
  } catch (const std::exception& e) {
    fmt::print(stderr, "asynevo: internal error: {}\n", e.what());
    return asynevo::cli::kExitError;
  }
  return asynevo::cli::kExitOk;
}
