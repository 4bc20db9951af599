// The start of a stream left out (`asynevo run --skip-ms`, io/skip_reader.hpp).
#include "asynevo/io/skip_reader.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

std::vector<Event> readAll(EventReader& reader, std::vector<uint64_t>* first_index = nullptr) {
  std::vector<Event> all;
  EventPacket packet;
  while (reader.read(packet)) {
    EXPECT_FALSE(packet.empty());
    if (first_index) first_index->push_back(packet.first_index);
    all.insert(all.end(), packet.events.begin(), packet.events.end());
  }
  return all;
}

TEST(SkipReader, DropsTheEventsBeforeTheCutAndKeepsRecordIndices) {
  TempDir dir;
  // Six events 0.1 s apart from 1.0 s; a cut 0.25 s after the first leaves the last three (1.3 s on).
  const std::string path =
      dir.write("events.txt", "1.0 1 2 1\n1.1 3 4 0\n1.2 5 6 1\n1.3 7 8 0\n1.4 9 10 1\n1.5 11 12 0\n");
  ReaderOptions options;
  options.packet_size = 2;  // the first packet is dropped whole, the cut falls inside the second
  auto reader = skipStartOfStream(openEventReader(path, options), 250'000'000);
  std::vector<uint64_t> first_index;
  const std::vector<Event> kept = readAll(*reader, &first_index);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept.front().t_ns, 1'300'000'000);
  EXPECT_EQ(kept.front().x, 7);
  EXPECT_EQ(kept.back().x, 11);
  EXPECT_EQ(first_index, (std::vector<uint64_t>{3, 4})) << "indices of the records in the file";
  EXPECT_EQ(reader->stats().events, 3u);
  EXPECT_EQ(reader->stats().skipped_at_start, 3u);
  EXPECT_EQ(reader->info().format, "ecd");
}

TEST(SkipReader, AnEventExactlyAtTheCutIsKeptAndZeroIsTheStreamItself) {
  TempDir dir;
  const std::string path = dir.write("events.txt", "1.0 1 2 1\n1.1 3 4 0\n1.2 5 6 1\n");
  auto at_cut = skipStartOfStream(openEventReader(path), 100'000'000);
  const std::vector<Event> kept = readAll(*at_cut);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept.front().t_ns, 1'100'000'000);

  auto whole = skipStartOfStream(openEventReader(path), 0);
  EXPECT_EQ(readAll(*whole).size(), 3u);
  EXPECT_EQ(whole->stats().skipped_at_start, 0u);
  EXPECT_THROW(skipStartOfStream(openEventReader(path), -1), std::invalid_argument);
}

TEST(SkipReader, ACutBeyondTheStreamIsAnErrorNamingTheFileAndItsSpan) {
  TempDir dir;
  const std::string path = dir.write("events.txt", "1.0 1 2 1\n1.5 3 4 0\n");
  auto reader = skipStartOfStream(openEventReader(path), 2'000'000'000);
  EventPacket packet;
  try {
    reader->read(packet);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("skipping the first 2.000 s"), std::string::npos) << what;
    EXPECT_NE(what.find("spans 0.500 s (2 events)"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace asynevo
