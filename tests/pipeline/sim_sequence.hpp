#pragma once
// Test helper: a short simulated sequence made once per build with 'asynevo simulate' and kept in the
// build folder, so the command-line tests that need one (end to end, determinism) do not each pay for
// the simulation. Safe under 'ctest -j': each process simulates into its own folder and renames it into
// place; a loser of the race discards its copy.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../cli/cli_test_util.hpp"
#include "../io/io_test_util.hpp"

namespace asynevo::testing {

/// A temporary folder unique to this test and process (io_test_util.hpp's TempDir carries the pid).
using UniqueTempDir = TempDir;

/// Path of the ECD-format folder for `scene`/`motion`/`duration_s` (seed 1), simulating it if needed.
/// Returns "" and sets `error` when the simulation failed.
inline std::string simulatedSequence(const std::string& scene, const std::string& motion, double duration_s,
                                     std::string& error) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(ASYNEVO_BINARY_DIR) / "test_sequences";
  const std::string name =
      scene + "_" + motion + "_" + std::to_string(static_cast<int>(duration_s * 1000)) + "ms";
  const fs::path folder = root / name;
  if (fs::exists(folder / "events.txt") && fs::exists(folder / "groundtruth.txt")) return folder.string();
  fs::create_directories(root);
  const fs::path mine = root / (name + ".tmp" + std::to_string(getpid()));
  fs::remove_all(mine);
  const CommandResult r = runAsynevo("simulate --scene " + scene + " --motion " + motion + " --duration " +
                                     std::to_string(duration_s) + " --seed 1 --out " + mine.string());
  if (r.exit_code != 0) {
    error = r.output;
    fs::remove_all(mine);
    return "";
  }
  std::error_code ec;
  fs::rename(mine, folder, ec);  // fails when another process got there first: use theirs
  if (ec) fs::remove_all(mine);
  return folder.string();
}

}  // namespace asynevo::testing
