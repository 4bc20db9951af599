// The sensor size on the command line: --sensor WxH on every command that reads events, a folder's
// sensor.yaml, a camchain's resolution without --config (run and track used to ignore it), a size that
// disagrees with a file's header, and a folder holding a Prophesee recording instead of events.txt.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::runAsynevo;
using testing::TempDir;

// Two events of a DAVIS346, outside a 240x180 sensor.
constexpr const char* kDavis346Events = "0.1 300 200 1\n0.2 345 259 0\n";
constexpr const char* kCamchain346 =
    "cam0:\n  camera_model: pinhole\n  distortion_model: equidistant\n  intrinsics: [226.4, 226.2, 173.6, 133.7]\n"
    "  distortion_coeffs: [-0.048, 0.011, -0.048, 0.018]\n  resolution: [346, 260]\n";
// EVT 3.0 words: TIME_HIGH 1, ADDR_Y 3, ADDR_X 5 ON (one event at (5, 3), t = 4096 us).
const std::string kEvt3Event("\x01\x80\x03\x00\x05\x28", 6);

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SensorFlag, MalformedValuesAreRejectedOnEveryCommandThatReadsEvents) {
  TempDir dir;
  dir.write("events.txt", "0.1 1 2 1\n");
  const std::string d = dir.path().string();
  for (const std::string& command : {"info --dataset " + d, "track --dataset " + d + " --out " + dir.file("t.txt"),
                                     "run --dataset " + d + " --out " + dir.file("run"),
                                     "convert --dataset " + d + " --out " + dir.file("e.aevt")}) {
    for (const char* bad : {"240", "0x180", "-1x5", "abcxdef"}) {
      const auto result = runAsynevo(command + " --sensor=" + bad);
      EXPECT_EQ(result.exit_code, 105) << command << " --sensor " << bad << "\n" << result.output;
      EXPECT_TRUE(contains(result.output, "--sensor: '" + std::string(bad) + "' is not WxH, the sensor's width and "
                                          "height in pixels (1..65535 each), e.g. 346x260"))
          << result.output;
    }
  }
}

TEST(SensorFlag, SetsTheSizeOnInfoTrackAndConvert) {
  TempDir dir;
  dir.write("events.txt", kDavis346Events);
  const std::string d = dir.path().string();
  auto result = runAsynevo("info --dataset " + d);  // the ECD default is too small
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(contains(result.output, "events.txt:1: pixel (300, 200) is outside the 240x180 sensor (size from the "
                                      "ECD text default, a DAVIS240C); set the sensor size with --sensor WxH, a "
                                      "sensor.yaml (width: W, height: H) in the dataset folder or a sensor: block in "
                                      "the configuration"))
      << result.output;

  result = runAsynevo("info --dataset " + d + " --sensor 346x260");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "sensor        346 x 260 (from --sensor)\n")) << result.output;

  result = runAsynevo("track --dataset " + d + " --sensor 346x260 --out " + dir.file("tracks.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.output;

  result = runAsynevo("convert --dataset " + d + " --sensor 346x260 --out " + dir.file("events.aevt"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "wrote 2 events (346x260)")) << result.output;
  // The .aevt now states the size; another --sensor contradicts it.
  result = runAsynevo("info --dataset " + dir.file("events.aevt") + " --sensor 640x480");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(contains(result.output, "events.aevt: sensor size 346x260 in the .aevt header differs from 640x480 set "
                                      "by --sensor"))
      << result.output;
}

TEST(SensorFlag, RunUsesTheFlag) {
  TempDir dir;
  dir.write("events.txt", kDavis346Events);
  dir.write("calib.txt", "226.4 226.2 173.6 133.7 0 0 0 0 0\n");
  const auto result = runAsynevo("run --dataset " + dir.path().string() + " --sensor 346x260 --out " + dir.file("run"));
  // Two events cannot initialize (exit 1), but they are read at the given size.
  EXPECT_TRUE(contains(result.output, "(ecd, 346x260)")) << result.output;
  EXPECT_TRUE(contains(result.output, "initialization never succeeded")) << result.output;
  EXPECT_TRUE(contains(readText(dir.file("run/stats.json")), "\"size_origin\": \"--sensor\""));
}

// Bug: without --config, run and track read ECD text at 240x180 even when the folder's camchain says
// 346x260 (run stopped at "calibration is for 346x260 pixels but the events are 240x180", track at the
// first pixel outside 240x180). info and convert already took the camchain's resolution.
TEST(SensorSizeFromCalibration, RunAndTrackTakeTheCamchainResolutionWithoutConfig) {
  TempDir dir;
  dir.write("events.txt", kDavis346Events);
  dir.write("camchain.yaml", kCamchain346);
  const std::string d = dir.path().string();
  auto result = runAsynevo("track --dataset " + d + " --out " + dir.file("tracks.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.output;

  result = runAsynevo("run --dataset " + d + " --out " + dir.file("run"));
  EXPECT_FALSE(contains(result.output, "calibration is for")) << result.output;
  EXPECT_TRUE(contains(result.output, "(ecd, 346x260)")) << result.output;
  EXPECT_TRUE(contains(result.output, "initialization never succeeded")) << result.output;
  EXPECT_TRUE(contains(readText(dir.file("run/stats.json")), "\"size_origin\": \"the calibration " + dir.file("camchain.yaml")))
      << readText(dir.file("run/stats.json"));
}

TEST(SensorYamlInFolder, SetsTheSizeAndRanksBelowConfigAndFlag) {
  TempDir dir;
  dir.write("events.txt", kDavis346Events);
  dir.write("sensor.yaml", "width: 346\nheight: 260\n");
  const std::string d = dir.path().string();
  auto result = runAsynevo("info --dataset " + d);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "sensor        346 x 260 (from " + dir.file("sensor.yaml") + ")\n")) << result.output;

  // A configuration without a sensor block leaves the folder's size alone; one with a block wins, with a note.
  const std::string no_block = dir.write("input.yaml", "input:\n  packet_size: 1000\n");
  result = runAsynevo("info --dataset " + d + " --config " + no_block);
  EXPECT_TRUE(contains(result.output, "sensor        346 x 260 (from " + dir.file("sensor.yaml") + ")\n")) << result.output;
  const std::string block = dir.write("big.yaml", "sensor:\n  width: 640\n  height: 480\n");
  result = runAsynevo("info --dataset " + d + " --config " + block);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "sensor        640 x 480 (from the configuration " + block + ")\n")) << result.output;
  EXPECT_TRUE(contains(result.output, "note: sensor size 640x480 from the configuration " + block + " overrides 346x260 from " +
                                          dir.file("sensor.yaml")))
      << result.output;
  result = runAsynevo("info --dataset " + d + " --config " + block + " --sensor 400x300");
  EXPECT_TRUE(contains(result.output, "sensor        400 x 300 (from --sensor)\n")) << result.output;

  dir.write("sensor.yaml", "width: 346\nheigth: 260\n");
  result = runAsynevo("info --dataset " + d);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(contains(result.output, "asynevo: error: " + dir.file("sensor.yaml") + ":2: unknown key 'heigth'"))
      << result.output;
}

TEST(SensorFlag, MustAgreeWithAPropheseeHeader) {
  TempDir dir;
  const std::string path = dir.write("rec.raw", "% evt 3.0\n% geometry 64x32\n% end\n" + kEvt3Event);
  auto result = runAsynevo("info --dataset " + path + " --sensor 64x32");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  result = runAsynevo("info --dataset " + path + " --sensor 640x480");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(contains(result.output, path + ": byte 10: sensor size 64x32 in the header differs from 640x480 set by "
                                             "--sensor (the file's own size is kept only when they agree"))
      << result.output;
}

// Bug: a folder holding a Prophesee recording (events.raw, events.dat) instead of events.txt was not read.
TEST(DatasetFolder, ReadsAPropheseeRecordingAndRejectsAmbiguity) {
  TempDir dir;
  dir.write("events.raw", "% evt 3.0\n% geometry 64x32\n% end\n" + kEvt3Event);
  const std::string d = dir.path().string();
  auto result = runAsynevo("info --dataset " + d);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "events file   " + dir.file("events.raw"))) << result.output;
  EXPECT_TRUE(contains(result.output, "format        evt3\n")) << result.output;

  dir.write("events.txt", "0.1 1 2 1\n");
  result = runAsynevo("info --dataset " + d);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(contains(result.output, d + ": several event files in this folder (events.raw, events.txt)")) << result.output;
  result = runAsynevo("info --dataset " + d + " --format evt3");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "format        evt3\n")) << result.output;
  result = runAsynevo("info --dataset " + d + " --format ecd");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "format        ecd\n")) << result.output;
}

TEST(DatasetFolder, ReadsAPropheseeDatRecording) {
  const std::string sample = testing::sharedFormatSample("dat/sample_ncars.dat");
  if (!std::filesystem::exists(sample)) GTEST_SKIP() << "sample recording " << sample << " not found (../shared/data missing)";
  TempDir dir;
  std::filesystem::copy_file(sample, dir.file("events.dat"));  // a copy in a temporary folder, not in the repository
  const auto result = runAsynevo("info --dataset " + dir.path().string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(contains(result.output, "format        dat\n")) << result.output;
  EXPECT_TRUE(contains(result.output, "events        2009\n")) << result.output;
}

}  // namespace
}  // namespace asynevo
