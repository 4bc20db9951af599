// DSEC's rectification map on the command line: found beside the events, named with --rectify-map, turned
// off with --rectify-map none, reported by info and convert, and a bad map is an error (exit code 1).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <utility>

#include "asynevo/io/event_reader.hpp"
#include "cli_test_util.hpp"
#include "dsec_fixture.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::runAsynevo;
using testing::TempDir;

// Raw (x, y) -> (x, y - 1): row 0 leaves the sensor.
std::pair<float, float> shiftUp(int x, int y) {
  return {static_cast<float>(x), static_cast<float>(y) - 1.0f};
}

TEST(DsecRectifyCli, InfoAndConvertReportTheMapAndTheDroppedEvents) {
  TempDir dir;
  testing::DsecEvents events;
  for (int i = 0; i < 40; ++i) {
    events.x.push_back(static_cast<uint16_t>(i % 8));
    events.y.push_back(static_cast<uint16_t>(i % 6));  // rows 0: 7 events
    events.t.push_back(100 * i);
    events.p.push_back(static_cast<uint8_t>(i % 2));
  }
  const std::string h5 = dir.file("events.h5");
  testing::writeDsecEvents(h5, events);
  const std::string map = dir.file("rectify_map.h5");
  testing::writeRectifyMap(map, testing::rectifyMapValues(8, 6, shiftUp), {6, 8, 2});

  const auto info = runAsynevo("info --dataset " + h5 + " --sensor 8x6");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("rectification " + map +
                             ": events in the rectified camera's pixels (rounded), 7 mapped "
                             "outside the sensor (dropped)"),
            std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("events        33\n"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("the calibration that applies is DSEC's rectified camera"), std::string::npos)
      << info.output;

  const auto raw = runAsynevo("info --dataset " + h5 + " --sensor 8x6 --rectify-map none");
  ASSERT_EQ(raw.exit_code, 0) << raw.output;
  EXPECT_NE(raw.output.find("rectification none: events in raw pixels"), std::string::npos) << raw.output;
  EXPECT_NE(raw.output.find("events        40\n"), std::string::npos) << raw.output;

  const std::string aevt = dir.file("rectified.aevt");
  const auto convert = runAsynevo("convert --dataset " + h5 + " --sensor 8x6 --out " + aevt);
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  EXPECT_NE(
      convert.output.find("note: events rectified by " + map + " (7 mapped outside the sensor, dropped)"),
      std::string::npos)
      << convert.output;
  const std::vector<Event> rectified = readAllEvents(aevt);
  ASSERT_EQ(rectified.size(), 33u);
  EXPECT_EQ(rectified[0].x, 1);  // event 1: raw (1, 1)
  EXPECT_EQ(rectified[0].y, 0);

  // A map named elsewhere; a bad one is an error naming the file and the dataset.
  const std::string other = dir.file("other.h5");
  testing::writeRectifyMap(other, testing::rectifyMapValues(8, 6, shiftUp), {8, 6, 2});
  const auto bad = runAsynevo("info --dataset " + h5 + " --sensor 8x6 --rectify-map " + other);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("asynevo: error: " + other + ": dataset 'rectify_map' has shape (8, 6, 2)"),
            std::string::npos)
      << bad.output;
}

// run: the summary names the map and the dropped events, stats.json records them, and a distorted calibration
// with rectified events is warned about. (Too few events to initialize: the run ends with that error after
// its summary.)
TEST(DsecRectifyCli, RunReportsTheMapAndWarnsAboutADistortedCalibration) {
  TempDir dir;
  constexpr int kW = 240, kH = 180;
  testing::DsecEvents events;
  for (int i = 0; i < 2000; ++i) {
    events.x.push_back(static_cast<uint16_t>((i * 7) % kW));
    events.y.push_back(static_cast<uint16_t>((i * 5) % kH));
    events.t.push_back(50 * i);
    events.p.push_back(static_cast<uint8_t>(i % 2));
  }
  testing::writeDsecEvents(dir.file("events.h5"), events);
  testing::writeRectifyMap(dir.file("rectify_map.h5"), testing::rectifyMapValues(kW, kH, shiftUp), {kH, kW, 2});
  dir.write("calib.txt", "50 50 32 24 -0.1 0.01 0 0 0\n");
  const auto run = runAsynevo("run --dataset " + dir.path().string() + " --sensor 240x180 --out " + dir.file("run"));
  EXPECT_NE(run.output.find("rectified       by " + dir.file("rectify_map.h5") + ": "), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("warning: the events are rectified by " + dir.file("rectify_map.h5") +
                            " but the calibration " + dir.file("calib.txt") + " has radtan distortion"),
            std::string::npos)
      << run.output;
  std::ifstream json(dir.file("run") + "/stats.json");
  const std::string stats((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(stats.find("\"rectify_map\": \"" + dir.file("rectify_map.h5") + "\""), std::string::npos) << stats;
  // Row 0 leaves the sensor: its events are the ones dropped.
  int dropped = 0;
  for (uint16_t y : events.y) dropped += y == 0 ? 1 : 0;
  EXPECT_NE(stats.find("\"rectified_outside\": " + std::to_string(dropped)), std::string::npos) << stats;
  // An undistorted calibration: no warning.
  dir.write("calib.txt", "50 50 32 24 0 0 0 0 0\n");
  const auto clean = runAsynevo("run --dataset " + dir.path().string() + " --sensor 240x180 --out " + dir.file("run2"));
  EXPECT_EQ(clean.output.find("warning: the events are rectified"), std::string::npos) << clean.output;
}

}  // namespace
}  // namespace asynevo
