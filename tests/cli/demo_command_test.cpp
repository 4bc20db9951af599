// 'asynevo demo': a short version of the built-in demo, run as a user would from a fresh folder
// (without --out), must simulate, run, evaluate and report.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../pipeline/sim_sequence.hpp"
#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::CommandResult;
using TempDir = testing::UniqueTempDir;

/// Runs asynevo with `arguments` inside `folder`.
CommandResult runAsynevoIn(const std::string& folder, const std::string& arguments) {
  const std::string command =
      "cd '" + folder + "' && " + std::string(ASYNEVO_BINARY_DIR) + "/bin/asynevo " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

TEST(DemoCommand, WritesIntoAsynevoDemoByDefaultAndReportsAccuracyAndSpeed) {
  const TempDir dir;
  // 1.5 s instead of 10 s keeps the test short (~8 s); figures are skipped (drawn by Python).
  const auto r = runAsynevoIn(dir.path().string(), "demo --duration 1.5 --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE           RMSE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("RTE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("real-time factor"), std::string::npos) << r.output;
  const std::filesystem::path demo = dir.path() / "asynevo_demo";
  EXPECT_NE(r.output.find(demo.string()), std::string::npos) << "it must say where it wrote\n" << r.output;
  for (const char* f : {"sequence/events.txt", "sequence/groundtruth.txt", "run/stamped_traj_estimate.txt",
                        "run/stamped_groundtruth.txt", "run/eval.json", "run/stats.json", "run/timing.csv"})
    EXPECT_TRUE(std::filesystem::exists(demo / f)) << f;
}

}  // namespace
}  // namespace asynevo
