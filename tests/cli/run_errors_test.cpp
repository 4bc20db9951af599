// 'asynevo run' on bad input: the errors a user meets first.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "../pipeline/sim_sequence.hpp"
#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::runAsynevo;
using TempDir = testing::UniqueTempDir;

TEST(RunCommand, MissingCalibrationIsAnErrorBeforeAnyProcessing) {
  const TempDir dir;
  std::filesystem::create_directories(dir.file("data"));
  std::filesystem::copy_file(dataPath("ecd/shapes_rotation/events.txt"), dir.file("data/events.txt"));
  const auto r = runAsynevo("run --dataset " + dir.file("data") + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no camera calibration"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--calib"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out"))) << "nothing may be written before the check";
}

TEST(RunCommand, AMissingCalibFileIsNamed) {
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --calib " +
                            dir.file("nope.txt") + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(dir.file("nope.txt")), std::string::npos) << r.output;
}

TEST(RunCommand, IncrementalBackendRunsTheFullHistorySmootherBaseline) {
  // The 0.1 s slice is too short to initialize (exit 1), but the run folder names the baseline.
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") +
                            " --backend incremental --out " + dir.file("out"));
  EXPECT_NE(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("full-history-smoother"), std::string::npos) << r.output;
  std::ifstream stats(dir.file("out/stats.json"));
  std::stringstream s;
  s << stats.rdbuf();
  EXPECT_NE(s.str().find("\"backend\": \"full-history-smoother\""), std::string::npos) << s.str();
}

TEST(RunCommand, FrozenIncrementalBackendIsNamedForWhatItIs) {
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") +
                            " --backend incremental-frozen --out " + dir.file("out"));
  EXPECT_NE(r.exit_code, 3) << r.output;
  std::ifstream stats(dir.file("out/stats.json"));
  std::stringstream s;
  s << stats.rdbuf();
  EXPECT_NE(s.str().find("\"backend\": \"full-history-smoother-frozen\""), std::string::npos) << s.str();
}

TEST(RunCommand, AnUnknownBackendIsAUsageError) {
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --backend isam2 --out " +
                            dir.file("out"));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--backend"), std::string::npos) << r.output;
}

TEST(RunCommand, NoTextureEndsWithTheInitializationMessageANonZeroExitAndPartialOutputs) {
  // Two seconds of uniform background noise (no structure): the frontend finds nothing to track.
  const TempDir dir;
  std::filesystem::create_directories(dir.file("noise"));
  std::ostringstream events;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> x(0, 239), y(0, 179), p(0, 1);
  int64_t t_us = 1000;
  for (int i = 0; i < 20000; ++i) {
    t_us += 100;
    events << t_us / 1000000 << '.' << std::to_string(1000000 + t_us % 1000000).substr(1) << ' ' << x(rng)
           << ' ' << y(rng) << ' ' << p(rng) << '\n';
  }
  dir.write("noise/events.txt", events.str());
  dir.write("noise/calib.txt",
            "199.092366 198.82882 132.192071 110.712283 -0.368436 0.150947 -0.000296 -0.000759 0\n");
  const auto r = runAsynevo("run --dataset " + dir.file("noise") + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("initialization never succeeded"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("20000 events"), std::string::npos) << r.output;
  for (const char* f : {"tracks.txt", "stats.json", "config.yaml", "stamped_traj_estimate.txt", "timing.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir.file(std::string("out/") + f))) << f;
  std::ifstream stats(dir.file("out/stats.json"));
  std::stringstream s;
  s << stats.rdbuf();
  EXPECT_NE(s.str().find("\"initialized\": false"), std::string::npos) << s.str();
}

TEST(RunCommand, ARealSliceRunsAndWritesEveryRunFolderFile) {
  // 0.1 s of ECD shapes_rotation: too short to initialize, but every file must be there and the
  // ground truth restricted to the event time span.
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --out " + dir.file("out"));
  EXPECT_NE(r.output.find("events          20000"), std::string::npos) << r.output;
  for (const char* f : {"stamped_traj_estimate.txt", "velocities.txt", "tracks.txt", "landmarks.ply",
                        "timing.csv", "stats.json", "config.yaml", "stamped_groundtruth.txt", "init_attempts.txt"})
    EXPECT_TRUE(std::filesystem::exists(dir.file(std::string("out/") + f))) << f;
  std::ifstream gt(dir.file("out/stamped_groundtruth.txt"));
  std::string line;
  int poses = 0;
  while (std::getline(gt, line)) {
    if (line.empty() || line[0] == '#') continue;
    const double t = std::stod(line.substr(0, line.find(' ')));
    EXPECT_GE(t, 2.097134001);
    EXPECT_LE(t, 2.195729000);
    ++poses;
  }
  EXPECT_GT(poses, 10);
}

TEST(RunCommand, SkipMsStartsTheRunLaterAndSaysWhatItLeftOut) {
  // --skip-ms 40 on the 0.1 s ECD slice (first event 2.097134001 s): the events, the pipeline's span
  // and the ground truth begin 40 ms later; stats.json says how many events were left out.
  const TempDir dir;
  const auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --skip-ms 40 --out " +
                            dir.file("out"));
  ASSERT_NE(r.output.find("before them skipped (--skip-ms)"), std::string::npos) << r.output;
  std::ifstream stats_file(dir.file("out/stats.json"));
  std::stringstream stats;
  stats << stats_file.rdbuf();
  EXPECT_NE(stats.str().find("\"skip_ms\": 40"), std::string::npos) << stats.str();
  const auto skipped_at = stats.str().find("\"events_skipped_at_start\": ");
  ASSERT_NE(skipped_at, std::string::npos);
  const long skipped = std::stol(stats.str().substr(skipped_at + 27));
  EXPECT_GT(skipped, 1000);
  EXPECT_LT(skipped, 20000);
  EXPECT_NE(r.output.find("events          " + std::to_string(20000 - skipped) + " "), std::string::npos)
      << r.output;
  std::ifstream gt(dir.file("out/stamped_groundtruth.txt"));
  std::string line;
  int poses = 0;
  while (std::getline(gt, line)) {
    if (line.empty() || line[0] == '#') continue;
    EXPECT_GE(std::stod(line.substr(0, line.find(' '))), 2.137134001);
    ++poses;
  }
  EXPECT_GT(poses, 5);

  const auto beyond = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --skip-ms 500 --out " +
                                 dir.file("out2"));
  EXPECT_EQ(beyond.exit_code, 1) << beyond.output;
  EXPECT_NE(beyond.output.find("no event is left after skipping the first 0.500 s"), std::string::npos)
      << beyond.output;
  const auto negative = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --skip-ms -5 --out " +
                                   dir.file("out3"));
  EXPECT_NE(negative.exit_code, 0) << negative.output;
  const auto huge = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --skip-ms 1e300 --out " +
                               dir.file("out4"));
  EXPECT_EQ(huge.exit_code, 1) << huge.output;
  EXPECT_NE(huge.output.find("--skip-ms must be a duration from 0 to 1e12 ms"), std::string::npos) << huge.output;
}

}  // namespace
}  // namespace asynevo
