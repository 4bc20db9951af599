#include <gtest/gtest.h>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::runAsynevo;
using testing::TempDir;

struct Expected {
  const char* folder;
  const char* events_line;
  const char* span_line;
};

TEST(InfoCommand, PrintsTheRightCountsAndSpansForEveryRealSlice) {
  const Expected slices[] = {
      {"shapes_rotation", "events        20000\n", "time span     2.097134001 .. 2.195729000 s"},
      {"poster_rotation", "events        30000\n", "time span     0.636764000 .. 0.660948999 s"},
      {"boxes_rotation", "events        30000\n", "time span     13.582595999 .. 13.595874999 s"},
      {"dynamic_rotation", "events        30000\n", "time span     19.098314000 .. 19.119366000 s"},
      {"slider_depth", "events        50000\n", "time span     0.003811000 .. 0.174156000 s"},
  };
  for (const auto& s : slices) {
    const auto result = runAsynevo("info --dataset " + dataPath(std::string("ecd/") + s.folder));
    EXPECT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find(s.events_line), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(s.span_line), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("sensor        240 x 180"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("format        ecd"), std::string::npos) << result.output;
  }
}

TEST(InfoCommand, ReportsCalibrationAndGroundTruthFiles) {
  const auto result = runAsynevo("info --dataset " + dataPath("ecd/shapes_rotation"));
  EXPECT_NE(result.output.find("calibration   " + dataPath("ecd/shapes_rotation/calib.txt")), std::string::npos);
  EXPECT_NE(result.output.find("ground truth  " + dataPath("ecd/shapes_rotation/groundtruth.txt")), std::string::npos);
  EXPECT_NE(result.output.find("fx=199.092"), std::string::npos) << result.output;
  // 11,883 mocap poses at ~200 Hz; the 98.6 ms slice holds about 20 of them (19 strictly inside) (shared/data/SOURCES.md).
  EXPECT_NE(result.output.find("11883 poses, 0.021"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("19 inside the event span"), std::string::npos) << result.output;
}

// Every bad-input case: the message names the file and line, and the exit code is 1.
TEST(InfoCommand, BadInputExitsWithOneAndNamesFileAndLine) {
  struct Case {
    const char* content;
    const char* message;
  };
  const Case cases[] = {
      {"0.1 1 2 1\n0.2 1 2\n", "events.txt:2: expected 4 fields 't x y p', found 3 (truncated line?)"},
      {"0.1 1 2 1\nx1 1 2 1\n", "events.txt:2: time 'x1' is not a finite number of seconds"},
      {"0.1 1 2 1\nnan 1 2 1\n", "events.txt:2: time 'nan' is not a finite number of seconds"},
      {"0.1 1 2 1\n-inf 1 2 1\n", "events.txt:2: time '-inf' is not a finite number of seconds"},
      {"0.1 1 2 1\n0.2 250 2 1\n", "events.txt:2: pixel (250, 2) is outside the 240x180 sensor"},
      {"0.1 1 2 1\n0.2 1 2 7\n", "events.txt:2: polarity 7 is not one of 0, 1, -1"},
      {"0.3 1 2 1\n0.2 1 2 1\n", "events.txt:2: time goes backwards by 100000000 ns"},
      {"", "events.txt: the event file is empty"},
      {"# only a comment\n", "events.txt: the file holds no events"},
  };
  for (const auto& c : cases) {
    TempDir dir;
    dir.write("events.txt", c.content);
    const auto result = runAsynevo("info --dataset " + dir.path().string());
    EXPECT_EQ(result.exit_code, 1) << c.content;
    EXPECT_NE(result.output.find("asynevo: error: " + dir.path().string() + "/" + c.message), std::string::npos)
        << "expected '" << c.message << "' in:\n"
        << result.output;
  }
}

TEST(InfoCommand, MissingDatasetAndEmptyFolder) {
  TempDir dir;
  auto result = runAsynevo("info --dataset " + dir.file("nothing"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find(dir.file("nothing") + ": no such file or folder"), std::string::npos) << result.output;
  result = runAsynevo("info --dataset " + dir.path().string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("no event file in this folder"), std::string::npos) << result.output;
}

TEST(InfoCommand, ConfigWithTypoIsRejectedWithItsLine) {
  TempDir dir;
  const auto config = dir.write("c.yaml", "sensor:\n  widht: 346\n");
  const auto result = runAsynevo("info --config " + config + " --dataset " + dataPath("ecd/shapes_rotation"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find(config + ":2: unknown configuration key 'sensor.widht'"), std::string::npos)
      << result.output;
}

TEST(Cli, UsageErrorsAreNonZero) {
  EXPECT_NE(runAsynevo("").exit_code, 0);
  EXPECT_NE(runAsynevo("info").exit_code, 0);  // --dataset is required
  EXPECT_NE(runAsynevo("no-such-command").exit_code, 0);
  EXPECT_EQ(runAsynevo("--help").exit_code, 0);
}

}  // namespace
}  // namespace asynevo

namespace asynevo {
namespace {

TEST(InfoCommand, SensorSizeComesFromAKalibrCalibration) {
  testing::TempDir dir;
  dir.write("events.txt", "0.1 300 200 1\n0.2 345 259 0\n");
  dir.write("camchain.yaml",
            "cam0:\n  camera_model: pinhole\n  distortion_model: equidistant\n  intrinsics: [226.4, 226.2, 173.6, "
            "133.7]\n  distortion_coeffs: [-0.048, 0.011, -0.048, 0.018]\n  resolution: [346, 260]\n");
  const auto result = testing::runAsynevo("info --dataset " + dir.path().string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("sensor        346 x 260"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("events        2\n"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace asynevo
