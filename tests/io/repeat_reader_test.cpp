// The repeated stream of `asynevo run --repeat` (io/repeat_reader.hpp).
#include "asynevo/io/repeat_reader.hpp"

#include <gtest/gtest.h>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

TEST(RepeatReader, PlaysTheStreamAgainContinuingInTime) {
  TempDir dir;
  // 4 events over 0.3 s: the mean interval is 75 ms.
  const std::string path = dir.write("events.txt", "1.0 1 2 1\n1.1 3 4 0\n1.2 5 6 1\n1.3 7 8 0\n");
  ReaderOptions options;
  options.packet_size = 3;  // passes end inside a packet of the inner reader
  auto reader = repeatEvents([&] { return openEventReader(path, options); }, 3);
  std::vector<Event> all;
  std::vector<uint64_t> first_index;
  EventPacket packet;
  while (reader->read(packet)) {
    first_index.push_back(packet.first_index);
    all.insert(all.end(), packet.events.begin(), packet.events.end());
  }
  ASSERT_EQ(all.size(), 12u);
  EXPECT_EQ(reader->stats().events, 12u);
  EXPECT_EQ(reader->info().format, "ecd");
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_GT(all[i].t_ns, all[i - 1].t_ns) << i;
  // Pass 2 starts 0.3 s + 75 ms after pass 1 started, with the same pixels.
  EXPECT_EQ(all[4].t_ns, all[0].t_ns + 375'000'000);
  EXPECT_EQ(all[8].t_ns, all[0].t_ns + 750'000'000);
  EXPECT_EQ(all[5].x, all[1].x);
  EXPECT_EQ(all[11].polarity, all[3].polarity);
  // Packet indices count the events of all passes.
  EXPECT_EQ(first_index, (std::vector<uint64_t>{0, 3, 4, 7, 8, 11}));
}

TEST(RepeatReader, OnePassIsTheStreamItselfAndAnEmptyPassIsAnError) {
  TempDir dir;
  const std::string path = dir.write("events.txt", "1.0 1 2 1\n1.1 3 4 0\n");
  auto once = repeatEvents([&] { return openEventReader(path); }, 1);
  EventPacket packet;
  ASSERT_TRUE(once->read(packet));
  EXPECT_EQ(packet.size(), 2u);
  EXPECT_FALSE(once->read(packet));
  EXPECT_THROW(repeatEvents([&] { return openEventReader(path); }, 0), std::invalid_argument);

  // A stream that has no events (a reader that ends at once) cannot be repeated.
  struct NoEvents : EventReader {
    StreamInfo info_{"nothing.aevt", "aevt", 240, 180, "the .aevt header", ""};
    ReaderStats stats_;
    bool read(EventPacket& p) override {
      p.events.clear();
      return false;
    }
    const StreamInfo& info() const override { return info_; }
    const ReaderStats& stats() const override { return stats_; }
  };
  try {
    auto reader = repeatEvents([] { return std::make_unique<NoEvents>(); }, 2);
    reader->read(packet);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.aevt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pass 1 of the repeated stream has no events"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace asynevo
