// DSEC's rectification map (rectify_map.h5) applied by the DSEC reader: fixtures written from the published
// layout (tests/io/dsec_fixture.hpp), exact rectified pixels, the events dropped outside the sensor, and
// every kind of bad map.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "dsec_fixture.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::DsecEvents;
using testing::rectifyMapValues;
using testing::TempDir;
using testing::writeDsecEvents;
using testing::writeRectifyMap;

constexpr int kWidth = 8, kHeight = 6;

ReaderOptions small(int packet_size = 65536, const std::string& map = "") {
  ReaderOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.size_origin = "--sensor";
  options.packet_size = packet_size;
  options.rectify_map = map;
  return options;
}

// Raw (x, y) -> (x + 0.4, y - 0.6), which rounds to (x, y - 1) (row 0 leaves the sensor), except for pixels
// that test the rounding and the borders.
std::pair<float, float> shiftUp(int x, int y) {
  if (x == 7 && y == 5) return {7.5f, 5.0f};    // x rounds to 8: outside
  if (x == 2 && y == 3) return {-0.5f, 1.0f};   // x rounds (away from zero) to -1: outside
  if (x == 3 && y == 3) return {-0.49f, 2.5f};  // (0, 3): 2.5 rounds away from zero
  if (x == 6 && y == 4) return {7.49f, 5.49f};  // (7, 5): the last pixel
  if (x == 5 && y == 2) return {1e30f, 2.0f};   // far outside
  return {static_cast<float>(x) + 0.4f, static_cast<float>(y) - 0.6f};
}

// Nine events at t = 10, 20, ... µs, on the pixels listed.
DsecEvents nineEvents() {
  const int pixels[9][2] = {{1, 1}, {3, 3}, {0, 0}, {7, 5}, {2, 3}, {6, 4}, {4, 2}, {5, 2}, {1, 5}};
  DsecEvents e;
  for (int i = 0; i < 9; ++i) {
    e.x.push_back(static_cast<uint16_t>(pixels[i][0]));
    e.y.push_back(static_cast<uint16_t>(pixels[i][1]));
    e.t.push_back(10 * (i + 1));
    e.p.push_back(static_cast<uint8_t>(i % 2));
  }
  return e;
}

TEST(DsecRectify, MapsEachEventToItsRoundedRectifiedPixelAndCountsThoseOutside) {
  TempDir dir;
  writeDsecEvents(dir.file("events.h5"), nineEvents());
  writeRectifyMap(dir.file("rectify_map.h5"), rectifyMapValues(kWidth, kHeight, shiftUp),
                  {kHeight, kWidth, 2});
  // Packets of 2 records: records 2 and 3 are both dropped, so the second packet reads on to records 4, 5.
  auto reader = openEventReader(dir.file("events.h5"), small(2));
  EXPECT_EQ(reader->info().rectify_map, dir.file("rectify_map.h5"));  // found beside the events
  EventPacket packet;
  std::vector<Event> all;
  std::vector<uint64_t> first_indices;
  while (reader->read(packet)) {
    EXPECT_FALSE(packet.events.empty());
    first_indices.push_back(packet.first_index);
    all.insert(all.end(), packet.events.begin(), packet.events.end());
  }
  const std::vector<Event> expected = {
      {10'000, 1, 0, -1}, {20'000, 0, 3, 1}, {60'000, 7, 5, 1}, {70'000, 4, 1, -1}, {90'000, 1, 4, -1}};
  EXPECT_EQ(all, expected);
  EXPECT_EQ(first_indices, (std::vector<uint64_t>{0, 2, 3, 4}));
  EXPECT_EQ(reader->stats().events, 5u);
  EXPECT_EQ(reader->stats().rectified_outside, 4u);
}

TEST(DsecRectify, NamedMapNoneAndNoMap) {
  TempDir dir;
  const DsecEvents events = nineEvents();
  writeDsecEvents(dir.file("events.h5"), events);
  // No map beside the events: raw pixels.
  auto raw = openEventReader(dir.file("events.h5"), small());
  EXPECT_EQ(raw->info().rectify_map, "");
  const std::vector<Event> raw_events = readAllEvents(dir.file("events.h5"), small());
  ASSERT_EQ(raw_events.size(), 9u);
  EXPECT_EQ(raw_events[1].x, 3);
  // A map named elsewhere (ReaderOptions::rectify_map, --rectify-map).
  writeRectifyMap(dir.file("maps.h5"), rectifyMapValues(kWidth, kHeight, shiftUp), {kHeight, kWidth, 2});
  auto named = openEventReader(dir.file("events.h5"), small(65536, dir.file("maps.h5")));
  EXPECT_EQ(named->info().rectify_map, dir.file("maps.h5"));
  EXPECT_EQ(readAllEvents(dir.file("events.h5"), small(65536, dir.file("maps.h5"))).size(), 5u);
  // "none" turns off the map beside the events.
  writeRectifyMap(dir.file("rectify_map.h5"), rectifyMapValues(kWidth, kHeight, shiftUp),
                  {kHeight, kWidth, 2});
  EXPECT_EQ(readAllEvents(dir.file("events.h5"), small()).size(), 5u);
  EXPECT_EQ(readAllEvents(dir.file("events.h5"), small(65536, "none")), raw_events);
  EXPECT_EQ(openEventReader(dir.file("events.h5"), small(65536, "none"))->info().rectify_map, "");
}

TEST(DsecRectify, BadMapsAreErrorsNamingTheFileAndDataset) {
  TempDir dir;
  writeDsecEvents(dir.file("events.h5"), nineEvents());
  const std::string map = dir.file("map.h5");
  const std::vector<float> good = rectifyMapValues(kWidth, kHeight, shiftUp);
  // Transposed (width, height, 2), and a map of another sensor.
  writeRectifyMap(map, good, {kWidth, kHeight, 2});
  EXPECT_EQ(
      testing::errorOf(dir.file("events.h5"), small(65536, map)),
      map +
          ": dataset 'rectify_map' has shape (8, 6, 2); the rectification map of the 8x6 sensor (size from "
          "--sensor) has shape (6, 8, 2): one (x, y) per raw pixel, indexed [y, x]");
  writeRectifyMap(map, std::vector<float>(4 * 3 * 2, 0.0f), {4, 3, 2});
  EXPECT_EQ(
      testing::errorOf(dir.file("events.h5"), small(65536, map)),
      map +
          ": dataset 'rectify_map' has shape (4, 3, 2); the rectification map of the 8x6 sensor (size from "
          "--sensor) has shape (6, 8, 2): one (x, y) per raw pixel, indexed [y, x]");
  writeRectifyMap(map, good, {kHeight * kWidth * 2});
  EXPECT_NE(testing::errorOf(dir.file("events.h5"), small(65536, map)).find("dataset 'rectify_map' has shape (96);"),
            std::string::npos);
  // Another dataset name.
  writeRectifyMap(map, good, {kHeight, kWidth, 2}, "map");
  EXPECT_EQ(testing::errorOf(dir.file("events.h5"), small(65536, map)),
            map +
                ": missing dataset 'rectify_map': a DSEC rectification map holds one dataset 'rectify_map' "
                "of shape "
                "(height, width, 2)");
  // A NaN entry is named by its [y, x].
  std::vector<float> nan = good;
  nan[2 * (2 * kWidth + 5)] = std::numeric_limits<float>::quiet_NaN();
  writeRectifyMap(map, nan, {kHeight, kWidth, 2});
  EXPECT_EQ(testing::errorOf(dir.file("events.h5"), small(65536, map)),
            map + ": dataset 'rectify_map' entry [2, 5] (y, x) is (nan, 2): not a finite pixel position");
  std::vector<float> inf = good;
  inf[2 * (kWidth + 1) + 1] = -std::numeric_limits<float>::infinity();
  writeRectifyMap(map, inf, {kHeight, kWidth, 2});
  EXPECT_NE(testing::errorOf(dir.file("events.h5"), small(65536, map))
                .find("entry [1, 1] (y, x) is (1.4, -inf): not a finite pixel position"),
            std::string::npos);
  // Integers instead of floats.
  writeRectifyMap(map, good, {kHeight, kWidth, 2}, "rectify_map", H5T_STD_I32LE);
  EXPECT_EQ(testing::errorOf(dir.file("events.h5"), small(65536, map)),
            map +
                ": dataset 'rectify_map' does not hold 32- or 64-bit floating-point numbers (its values are "
                "4 bytes "
                "each; corrupt file?)");
  // A missing file, a file that is not HDF5.
  EXPECT_EQ(testing::errorOf(dir.file("events.h5"), small(65536, dir.file("nope.h5"))),
            dir.file("nope.h5") +
                ": cannot open the rectification map as HDF5 (missing, unreadable or truncated file)");
  // A broken map beside the events is an error too (not skipped): it was meant to be used.
  writeRectifyMap(dir.file("rectify_map.h5"), good, {kWidth, kHeight, 2});
  EXPECT_NE(testing::errorOf(dir.file("events.h5"), small())
                .find(dir.file("rectify_map.h5") + ": dataset 'rectify_map' has "
                                                   "shape (8, 6, 2)"),
            std::string::npos);
}

TEST(DsecRectify, OtherFormatsRejectANamedMap) {
  TempDir dir;
  const std::string events = dir.write("events.txt", "0.1 1 1 1\n");
  writeRectifyMap(dir.file("map.h5"), rectifyMapValues(kWidth, kHeight, shiftUp), {kHeight, kWidth, 2});
  EXPECT_EQ(testing::errorOf(events, small(65536, dir.file("map.h5"))),
            events + ": a rectification map (" + dir.file("map.h5") +
                ") applies to DSEC-style HDF5 events only, and this file is of format ecd");
  EXPECT_EQ(readAllEvents(events, small(65536, "none")).size(), 1u);
}

}  // namespace
}  // namespace asynevo
