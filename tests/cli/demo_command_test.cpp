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

using TempDir = testing::UniqueTempDir;

TEST(DemoCommand, WritesIntoAsynevoDemoByDefaultAndReportsAccuracyAndSpeed) {
  const TempDir dir;
  // 1.5 s instead of 10 s keeps the test short (~8 s); figures are skipped (drawn by Python).
  const auto r = testing::runAsynevo("demo --duration 1.5 --no-plots", dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE           RMSE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("RTE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("velocity      RMSE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("direction     median"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("real-time factor"), std::string::npos) << r.output;
  const std::filesystem::path demo = dir.path() / "asynevo_demo";
  EXPECT_NE(r.output.find(demo.string()), std::string::npos) << "it must say where it wrote\n" << r.output;
  for (const char* f : {"sequence/events.txt", "sequence/groundtruth.txt", "run/stamped_traj_estimate.txt",
                        "run/stamped_groundtruth.txt", "run/eval.json", "run/stats.json", "run/timing.csv"})
    EXPECT_TRUE(std::filesystem::exists(demo / f)) << f;
}

}  // namespace
}  // namespace asynevo
