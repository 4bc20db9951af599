// 'asynevo run --frames DIR': the frame-based KLT baseline (docs/results/repeated_texture.md) end to end
// on a short simulated sequence, and the errors of a bad frame folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::runAsynevo;
using testing::TempDir;

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double jsonNumber(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": *([-0-9.eE+]+)"))) return -1;
  return std::stod(m[1].str());
}

TEST(RunFrames, AFolderWithoutImagesTxtIsNamed) {
  const TempDir dir;
  std::filesystem::create_directories(dir.file("frames"));
  const auto r = runAsynevo("run --frames " + dir.file("frames") + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(dir.file("frames") + "/images.txt"), std::string::npos) << r.output;
}

TEST(RunFrames, DatasetAndFramesTogetherOrNeitherAreRefused) {
  const TempDir dir;
  auto r = runAsynevo("run --dataset " + dataPath("ecd/shapes_rotation") + " --frames " +
                      dir.path().string() + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("exactly one of --dataset"), std::string::npos) << r.output;
  r = runAsynevo("run --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("exactly one of --dataset"), std::string::npos) << r.output;
}

TEST(RunFrames, AnUnreadableFrameIsNamed) {
  const TempDir dir;
  const std::string frames = dir.file("frames");
  // Two frames (0.6 s at 2 Hz), then the second replaced by a text file. A mis-sized frame is named
  // the same way (tests/frames/frame_folder_test.cpp).
  const auto sim = runAsynevo(
      "simulate --scene grating --motion speed-ramp --duration 0.6 --frame-rate 2 --out " + frames);
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  std::filesystem::copy_file(dataPath("ecd/shapes_rotation/calib.txt"), frames + "/images/frame_00000001.png",
                             std::filesystem::copy_options::overwrite_existing);
  const auto r = runAsynevo("run --frames " + frames + " --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(frames + "/images/frame_00000001.png"), std::string::npos) << r.output;
}

// 1.5 s of the grating scene at walking speed (1.4 m/s, no aliasing) with 30 Hz frames: ~2 s to
// simulate, ~1 s per run.
TEST(RunFrames, WalkingPastTheGratingIsTrackedAndDeterministic) {
  const TempDir dir;
  const std::string seq = dir.file("seq");
  const auto sim =
      runAsynevo("simulate --scene grating --motion speed-ramp --duration 1.5 --frame-rate 30 --out " + seq);
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const std::string out = dir.file("run");
  const auto run = runAsynevo("run --frames " + seq + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("frames          46 over 1.500 s (240x180, KLT baseline, 3 pyramid levels)"),
            std::string::npos)
      << run.output;
  const auto ev = runAsynevo("eval --gt " + out + "/stamped_groundtruth.txt --est " + out +
                             "/stamped_traj_estimate.txt --out " + out);
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  const std::string json = readFile(out + "/eval.json");
  // Measured at the commit of this test: ATE 3.7 mm on the 2.1 m path, velocity RMSE 2.1 % of 1.4 m/s.
  EXPECT_LT(jsonNumber(json.substr(json.find("\"ate\"")), "rmse"), 0.02) << json;
  EXPECT_LT(jsonNumber(json, "linear_rmse_perc_of_mean_speed"), 6.0) << json;
  // One thread, no timing: a second run writes the same trajectory.
  const auto again = runAsynevo("run --frames " + seq + " --out " + dir.file("again"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(readFile(out + "/stamped_traj_estimate.txt"),
            readFile(dir.file("again") + "/stamped_traj_estimate.txt"));
}

}  // namespace
}  // namespace asynevo
