#include <gtest/gtest.h>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::TempDir;

struct SliceFacts {
  const char* name;
  std::size_t events;
  int64_t first_ns;
  int64_t last_ns;
};

// Facts from tests/data/SOURCES.md (counts and spans of the bundled real ECD slices).
const SliceFacts kSlices[] = {
    {"shapes_rotation", 20000, 2'097'134'001, 2'195'729'000},
    {"poster_rotation", 30000, 636'764'000, 660'949'000},
    {"boxes_rotation", 30000, 13'582'596'000, 13'595'875'000},
    {"dynamic_rotation", 30000, 19'098'314'000, 19'119'366'000},
    {"slider_depth", 50000, 3'811'000, 174'156'000},
};

TEST(EcdReader, RealSlicesHaveTheDocumentedCountsAndSpans) {
  for (const auto& slice : kSlices) {
    SCOPED_TRACE(slice.name);
    const auto events = readAllEvents(dataPath(std::string("ecd/") + slice.name + "/events.txt"));
    ASSERT_EQ(events.size(), slice.events);
    // SOURCES.md gives spans to the microsecond; the files carry float-printing noise below that.
    EXPECT_NEAR(events.front().t_ns, slice.first_ns, 1000);
    EXPECT_NEAR(events.back().t_ns, slice.last_ns, 1000);
    int on = 0;
    for (std::size_t i = 0; i < events.size(); ++i) {
      ASSERT_LT(events[i].x, 240);
      ASSERT_LT(events[i].y, 180);
      ASSERT_TRUE(events[i].polarity == 1 || events[i].polarity == -1);
      if (i > 0) {
        ASSERT_GE(events[i].t_ns, events[i - 1].t_ns);
      }
      on += events[i].polarity > 0;
    }
    EXPECT_GT(on, 0);
    EXPECT_LT(on, static_cast<int>(events.size()));
  }
}

TEST(EcdReader, FirstEventsOfShapesRotationAreExact) {
  const auto events = readAllEvents(dataPath("ecd/shapes_rotation/events.txt"));
  // First lines of the file: "2.097134001 162 27 0", "2.09714 77 45 0".
  EXPECT_EQ(events[0], (Event{2'097'134'001, 162, 27, -1}));
  EXPECT_EQ(events[1], (Event{2'097'140'000, 77, 45, -1}));
}

TEST(EcdReader, StreamsInBoundedPackets) {
  ReaderOptions options;
  options.packet_size = 4096;
  auto reader = openEventReader(dataPath("ecd/shapes_rotation/events.txt"), options);
  EXPECT_EQ(reader->info().format, "ecd");
  EXPECT_EQ(reader->info().width, 240);
  EXPECT_EQ(reader->info().height, 180);
  EventPacket packet;
  std::size_t total = 0, packets = 0;
  while (reader->read(packet)) {
    EXPECT_LE(packet.size(), 4096u);
    EXPECT_EQ(packet.first_index, total);
    total += packet.size();
    ++packets;
  }
  EXPECT_EQ(total, 20000u);
  EXPECT_EQ(packets, 5u);
  EXPECT_EQ(reader->stats().events, 20000u);
  EXPECT_FALSE(reader->read(packet));
  EXPECT_TRUE(packet.empty());
}

TEST(EcdReader, AcceptsCommentsBlankLinesTabsCrlfAndMissingFinalNewline) {
  TempDir dir;
  const auto path = dir.write("events.txt", "# a comment\n\n0.5 1 2 1\r\n0.6\t3\t4\t0\n  0.7 5 6 -1");
  ReaderOptions options;
  auto reader = openEventReader(path, options);
  EventPacket packet;
  ASSERT_TRUE(reader->read(packet));
  ASSERT_EQ(packet.size(), 3u);
  EXPECT_EQ(packet.events[0], (Event{500'000'000, 1, 2, 1}));
  EXPECT_EQ(packet.events[1], (Event{600'000'000, 3, 4, -1}));
  EXPECT_EQ(packet.events[2], (Event{700'000'000, 5, 6, -1}));
  EXPECT_EQ(reader->stats().skipped_lines, 2u);
}

TEST(EcdReader, LinesLongerThanTheBufferAcrossChunkBoundariesParseCorrectly) {
  // Enough lines to cross several 1 MiB buffer refills; every line must survive the boundary.
  TempDir dir;
  std::string text;
  for (int i = 0; i < 100000; ++i) text += std::to_string(i) + ".123456789 " + std::to_string(i % 240) + " 7 1\n";
  const auto events = readAllEvents(dir.write("events.txt", text));
  ASSERT_EQ(events.size(), 100000u);
  for (int i = 0; i < 100000; ++i) {
    ASSERT_EQ(events[i].t_ns, int64_t{i} * 1'000'000'000 + 123'456'789) << i;
    ASSERT_EQ(events[i].x, i % 240);
  }
}

TEST(EcdReader, SmallTimeReversalWithinToleranceIsClampedAndCounted) {
  TempDir dir;
  const auto path = dir.write("events.txt", "1.000002 0 0 1\n1.000001 0 0 1\n1.000003 0 0 1\n");
  ReaderOptions options;
  options.max_time_reversal_ns = 5000;
  auto reader = openEventReader(path, options);
  EventPacket packet;
  ASSERT_TRUE(reader->read(packet));
  EXPECT_EQ(packet.events[1].t_ns, 1'000'002'000);
  EXPECT_EQ(reader->stats().clamped_times, 1u);
}

// Each bad input gets an error naming the file and the line.
struct BadCase {
  const char* content;
  const char* message;
};

// ECD text stores no sensor size: an out-of-sensor error says which size was used and how to set another.
#define ECD_SIZE_NOTE                                                                                          \
  " (size from the ECD text default, a DAVIS240C); set the sensor size with --sensor WxH, a sensor.yaml "     \
  "(width: W, height: H) in the dataset folder or a sensor: block in the configuration"

TEST(EcdReader, BadInputNamesFileAndLine) {
  const BadCase cases[] = {
      {"0.1 1 2 1\n0.2 1 2\n", ":2: expected 4 fields 't x y p', found 3 (truncated line?)"},
      {"0.1 1 2 1 9\n", ":1: expected 4 fields 't x y p', found 5 or more"},
      {"0.1 1 2 1\nabc 1 2 1\n", ":2: time 'abc' is not a finite number of seconds"},
      {"nan 1 2 1\n", ":1: time 'nan' is not a finite number of seconds"},
      {"inf 1 2 1\n", ":1: time 'inf' is not a finite number of seconds"},
      {"0.1 1.5 2 1\n", ":1: x '1.5' is not an integer"},
      {"0.1 1 y 1\n", ":1: y 'y' is not an integer"},
      {"0.1 240 2 1\n", ":1: pixel (240, 2) is outside the 240x180 sensor" ECD_SIZE_NOTE},
      {"0.1 1 180 1\n", ":1: pixel (1, 180) is outside the 240x180 sensor" ECD_SIZE_NOTE},
      {"0.1 -1 2 1\n", ":1: pixel (-1, 2) is outside the 240x180 sensor" ECD_SIZE_NOTE},
      {"0.1 1 2 2\n", ":1: polarity 2 is not one of 0, 1, -1"},
      {"0.2 1 2 1\n0.1 1 2 1\n",
       ":2: time goes backwards by 100000000 ns (tolerance input.max_time_reversal_us = 0); the events must "
       "be sorted by time"},
  };
  for (const auto& c : cases) {
    TempDir dir;
    const auto path = dir.write("events.txt", c.content);
    try {
      readAllEvents(path);
      ADD_FAILURE() << "no error for: " << c.content;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), path + c.message);
    }
  }
}

TEST(EcdReader, MissingAndEmptyFiles) {
  TempDir dir;
  try {
    openEventReader(dir.file("nope.txt"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("nope.txt") + ": cannot open event file: No such file or directory");
  }
  const auto empty = dir.write("empty.txt", "");
  try {
    openEventReader(empty);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), empty + ": the event file is empty");
  }
}

TEST(EcdReader, UnknownBinaryContentIsRejected) {
  TempDir dir;
  const auto path = dir.write("events.bin", std::string("\x01\x02\x00\x03garbage", 10));
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown binary format"), std::string::npos) << e.what();
  }
}

TEST(EcdReader, ConfiguredSensorSizeIsUsedForTheBoundsCheck) {
  TempDir dir;
  const auto path = dir.write("events.txt", "0.1 300 200 1\n");
  ReaderOptions options;
  options.width = 346;
  options.height = 260;
  EXPECT_EQ(readAllEvents(path, options).size(), 1u);
  EXPECT_THROW(readAllEvents(path), InputError);
}

}  // namespace
}  // namespace asynevo
