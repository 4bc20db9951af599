#include "asynevo/io/event_file.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::TempDir;

/// `events` as a 240x180 .aevt file at `path`.
void writeAevt(const std::string& path, const std::vector<Event>& events) {
  EventFileWriter writer(path, 240, 180);
  writer.write(events.data(), events.size());
  writer.close();
}

TEST(EventFile, RoundTripsARealSliceExactly) {
  TempDir dir;
  const auto original = readAllEvents(dataPath("ecd/poster_rotation/events.txt"));
  const auto path = dir.file("events.aevt");
  {
    EventFileWriter writer(path, 240, 180);
    writer.write(original.data(), 12345);
    writer.write(original.data() + 12345, original.size() - 12345);
    writer.close();
  }
  EXPECT_EQ(std::filesystem::file_size(path), 64 + 16 * original.size());
  ReaderOptions options;
  options.packet_size = 7000;
  auto reader = openEventReader(path, options);
  EXPECT_EQ(reader->info().format, "aevt");
  EXPECT_EQ(reader->info().width, 240);
  const auto reread = readAllEvents(path);
  EXPECT_EQ(reread, original);
}

TEST(EventFile, SameEventsGiveIdenticalBytes) {
  TempDir dir;
  const std::vector<Event> events = {{10, 1, 2, 1}, {20, 3, 4, -1}};
  for (const char* name : {"a.aevt", "b.aevt"}) {
    EventFileWriter writer(dir.file(name), 240, 180);
    writer.write(events.data(), events.size());
    writer.close();
  }
  std::ifstream a(dir.file("a.aevt"), std::ios::binary), b(dir.file("b.aevt"), std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(bytes_a, bytes_b);
}

TEST(EventFile, TruncatedFileIsReportedWithCounts) {
  TempDir dir;
  const auto path = dir.file("events.aevt");
  writeAevt(path, std::vector<Event>(100, Event{5, 1, 1, 1}));
  std::filesystem::resize_file(path, 64 + 16 * 50 + 3);
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": truncated or corrupt .aevt file: the header announces 100 events "
                                         "(1664 bytes) but the file has 867 bytes");
  }
  std::filesystem::resize_file(path, 30);
  EXPECT_THROW(openEventReader(path), InputError);
}

TEST(EventFile, OutOfSensorRecordIsReportedByIndex) {
  TempDir dir;
  const auto path = dir.file("events.aevt");
  writeAevt(path, {{1, 1, 1, 1}, {2, 300, 1, 1}});
  try {
    readAllEvents(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": record 1: pixel (300, 1) is outside the 240x180 sensor (size from the .aevt header)");
  }
}

// A time step back across most of the int64 range (found 2026-11-26 by the aevt_events fuzz harness):
// the checker's signed difference overflowed (UBSan); in a normal build the wrapped difference was
// negative, so the event was clamped and accepted instead of rejected.
TEST(EventFile, TimeStepBackAcrossTheInt64RangeIsReported) {
  TempDir dir;
  const auto path = dir.file("events.aevt");
  writeAevt(path, {{1, 1, 1, 1}, {INT64_MIN, 1, 1, 1}});
  try {
    readAllEvents(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).substr(0, path.size() + 57),
              path + ": record 1: time goes backwards by 9223372036854775809 ns");
  }
}

// An event count whose byte size wraps around 64 bits (2^60 + 2 events: 16 * count wraps to 32 bytes)
// matched the size of a file with 2 records, and the reader promised 2^60 events.
TEST(EventFile, CountWhoseByteSizeWrapsIsRejected) {
  TempDir dir;
  const auto path = dir.file("events.aevt");
  writeAevt(path, {{1, 1, 1, 1}, {2, 1, 1, 1}});
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(24);  // magic 8, version, width, height, record size: 4 each; then the uint64 count
    const uint64_t count = (uint64_t{1} << 60) + 2;
    f.write(reinterpret_cast<const char*>(&count), sizeof(count));
  }
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": corrupt .aevt file: the header announces 1152921504606846978 events, more than any file can hold");
  }
}

}  // namespace
}  // namespace asynevo
