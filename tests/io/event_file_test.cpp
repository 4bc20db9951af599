#include "asynevo/io/event_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::TempDir;

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
  {
    const std::vector<Event> events(100, Event{5, 1, 1, 1});
    EventFileWriter writer(path, 240, 180);
    writer.write(events.data(), events.size());
    writer.close();
  }
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
  {
    const std::vector<Event> events = {{1, 1, 1, 1}, {2, 300, 1, 1}};
    EventFileWriter writer(path, 240, 180);
    writer.write(events.data(), events.size());
    writer.close();
  }
  try {
    readAllEvents(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": record 1: pixel (300, 1) is outside the 240x180 sensor (size from the .aevt header)");
  }
}

}  // namespace
}  // namespace asynevo
