// ROS1 bag (format 2.0) reader.
//
// Three kinds of input:
// - the real sample bag ../shared/data/formats/rosbag/test_events_1.bag (event_camera_msgs/EventPacket,
//   EVT 3.0; Apache-2.0, not copied here); expected values from ../shared/data/SOURCES.md. Skipped when
//   the shared folder is missing.
// - bags built byte by byte in the tests from the format specification (tests/io/rosbag_fixture.hpp),
//   with dvs_msgs/EventArray and EventPacket messages, uncompressed and lz4/bz2 chunks (compressed here
//   with liblz4's frame API and libbz2), and every kind of bad input.
// - two small bags written by the ROS library's own writer (tests/data/rosbag/, see tests/data/SOURCES.md),
//   so compressed chunks as ROS writes them (roslz4 frames, bz2) are read too.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "chunk_compression.hpp"
#include "io_test_util.hpp"
#include "rosbag_fixture.hpp"

namespace asynevo {
namespace {

namespace bag = testing::bag;
using testing::errorOf;
using testing::ev;
using testing::TempDir;

std::string sample(const std::string& relative) { return std::string(ASYNEVO_SHARED_DATA_DIR) + "/formats/" + relative; }

const bag::Connection kDvs{0, "/dvs/events", bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
const bag::Connection kImu{1, "/dvs/imu", "sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2", "(not needed)"};
const bag::Connection kDvs2{2, "/dvs_right/events", bag::kEventArrayType, bag::kEventArrayMd5,
                            bag::kEventArrayDefinition};
const bag::Connection kPackets{3, "/event_camera/events", bag::kEventPacketType, bag::kEventPacketMd5, "(definition)"};

constexpr uint64_t kT0 = 1'600'000'000'000'000'000ull;  // ns, a Unix time as a ROS recorder writes

/// Events t = kT0 + i µs at (i % 240, i % 180), alternating polarity.
std::vector<bag::DvsEvent> dvsEvents(int first, int count) {
  std::vector<bag::DvsEvent> events;
  for (int i = first; i < first + count; ++i) {
    events.push_back({static_cast<uint16_t>(i % 240), static_cast<uint16_t>(i % 180), kT0 + uint64_t(i) * 1000,
                      i % 2 == 0});
  }
  return events;
}

Event expected(int i) {
  Event e;
  e.t_ns = static_cast<int64_t>(kT0 + uint64_t(i) * 1000);
  e.x = static_cast<uint16_t>(i % 240);
  e.y = static_cast<uint16_t>(i % 180);
  e.polarity = i % 2 == 0 ? 1 : -1;
  return e;
}

bag::Message dvsMessage(int first, int count, uint32_t conn = 0) {
  return {conn, kT0 + uint64_t(first) * 1000, bag::eventArray(240, 180, dvsEvents(first, count))};
}
bag::Message imuMessage(int i) { return {1, kT0 + uint64_t(i) * 5000, std::string(300, 'i')}; }

/// Two chunks: 3 EventArray messages (100, 0 and 250 events) and IMU messages between them.
std::string dvsBag(const std::function<std::string(const std::string&)>& compress = nullptr,
                   const std::string& compression = "none") {
  bag::Chunk a{{dvsMessage(0, 100), imuMessage(0), dvsMessage(100, 0)}, compression, compress};
  bag::Chunk b{{imuMessage(1), dvsMessage(100, 250), imuMessage(2)}, compression, compress};
  return bag::buildBag({kDvs, kImu}, {a, b});
}

void expectDvsEvents(const std::vector<Event>& events) {
  ASSERT_EQ(events.size(), 350u);
  for (int i = 0; i < 350; ++i) ASSERT_EQ(events[i], expected(i)) << "event " << i;
}

// ---------------------------------------------------------------------------------------------------

TEST(RosbagSample, EventPacketBagMatchesItsSourceFigures) {
  const std::string path = sample("rosbag/test_events_1.bag");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (the shared data folder is missing)";
  auto reader = openEventReader(path);  // format auto
  EXPECT_EQ(reader->info().format, "rosbag");
  EXPECT_EQ(reader->info().width, 640);
  EXPECT_EQ(reader->info().height, 480);
  uint64_t events = 0, on = 0;
  int64_t last = INT64_MIN;
  bool sorted = true;
  EventPacket packet;
  while (reader->read(packet)) {
    for (const Event& e : packet.events) {
      ++events;
      on += e.polarity > 0 ? 1 : 0;
      sorted = sorted && e.t_ns >= last;
      last = e.t_ns;
    }
  }
  EXPECT_EQ(events, 343474u);
  EXPECT_EQ(on, 125183u);
  EXPECT_EQ(events - on, 218291u);
  EXPECT_TRUE(sorted);
  EXPECT_EQ(reader->stats().trigger_events, 2079u + 2078u);
  ASSERT_EQ(reader->stats().streams.size(), 1u);
  const ContainerStream& topic = reader->stats().streams[0];
  EXPECT_EQ(topic.name, "/event_camera/events");
  EXPECT_EQ(topic.type, "event_camera_msgs/EventPacket");
  EXPECT_EQ(topic.packets, 517u);
  EXPECT_EQ(topic.elements, 343474u);
  EXPECT_TRUE(topic.delivered);
}

TEST(RosbagSample, PacketSizeDoesNotChangeTheEvents) {
  const std::string path = sample("rosbag/test_events_1.bag");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (the shared data folder is missing)";
  ReaderOptions small;
  small.packet_size = 7;  // vectors split across packets
  const std::vector<Event> a = readAllEvents(path);
  const std::vector<Event> b = readAllEvents(path, small);
  ASSERT_EQ(a.size(), 343474u);
  EXPECT_TRUE(a == b);
}

// ---------------------------------------------------------------------------------------------------

TEST(RosbagReader, ReadsEventArraysFromASpecBuiltBag) {
  TempDir dir;
  const std::string path = dir.write("events.bag", dvsBag());
  auto reader = openEventReader(path);
  EXPECT_EQ(reader->info().format, "rosbag");
  EXPECT_EQ(reader->info().width, 240);
  EXPECT_EQ(reader->info().height, 180);
  EXPECT_EQ(reader->info().size_origin, "the bag's messages");
  std::vector<Event> all;
  EventPacket packet;
  while (reader->read(packet)) all.insert(all.end(), packet.events.begin(), packet.events.end());
  expectDvsEvents(all);
  const auto& streams = reader->stats().streams;
  ASSERT_EQ(streams.size(), 2u);
  EXPECT_EQ(streams[0].name, "/dvs/events");
  EXPECT_EQ(streams[0].packets, 3u);
  EXPECT_EQ(streams[0].elements, 350u);
  EXPECT_TRUE(streams[0].delivered);
  EXPECT_EQ(streams[1].name, "/dvs/imu");
  EXPECT_EQ(streams[1].type, "sensor_msgs/Imu");
  EXPECT_EQ(streams[1].packets, 3u);
  EXPECT_FALSE(streams[1].delivered);
  // Packets smaller than a message, and an explicit format and topic, give the same events.
  ReaderOptions options;
  options.packet_size = 33;
  options.format = "rosbag";
  options.topic = "/dvs/events";
  expectDvsEvents(readAllEvents(path, options));
}

TEST(RosbagReader, ReadsCompressedChunks) {
  TempDir dir;
  expectDvsEvents(readAllEvents(dir.write("lz4.bag", dvsBag(bag::lz4, "lz4"))));
  expectDvsEvents(readAllEvents(dir.write("bz2.bag", dvsBag(bag::bz2, "bz2"))));
}

TEST(RosbagReader, ReadsBagsWrittenByTheRosLibrary) {
  // Written with librosbag-storage's Bag::write (tests/data/rosbag/SOURCES in tests/data/SOURCES.md): the
  // same 350 events in messages of 100, 0 and 250, with lz4 and with bz2 chunks.
  for (const char* name : {"rosbag/dvs_lz4.bag", "rosbag/dvs_bz2.bag"}) {
    SCOPED_TRACE(name);
    expectDvsEvents(readAllEvents(testing::dataPath(name)));
  }
}

TEST(RosbagReader, EventPacketPayloadsDecodeAsOneEvt3Stream) {
  // One EVT 3.0 stream split across three messages, a vector word's events split across packets: the
  // decoder's state (time, row, vector base) carries over from message to message.
  auto w = [](std::initializer_list<uint32_t> words) {
    std::string s;
    for (uint32_t x : words) s += bag::u16(x);
    return s;
  };
  const std::string p1 = w({0x8000 | 1, 0x6000 | 5, 0x0000 | 7});        // time high 1, low 5, y 7
  const std::string p2 = w({0x2000 | (1 << 11) | 3, 0x3000 | 10, 0x4000 | 0x805});  // x 3 ON; base 10 OFF; vect12
  const std::string p3 = w({0x6000 | 9, 0x2000 | 1, 0xA000 | 1});        // time low 9, x 1 OFF, a trigger
  bag::Chunk chunk{{{3, kT0, bag::eventPacket(64, 32, "evt3", p1)},
                    {3, kT0 + 1, bag::eventPacket(64, 32, "evt3", p2, 1)},
                    {3, kT0 + 2, bag::eventPacket(64, 32, "evt3", p3, 2)}}};
  TempDir dir;
  const std::string path = dir.write("packets.bag", bag::buildBag({kPackets}, {chunk}));
  const int64_t t = ((1 << 12) | 5) * 1000;
  const std::vector<Event> want = {ev(t / 1000, 3, 7, 1), ev(t / 1000, 10, 7, -1), ev(t / 1000, 12, 7, -1),
                                   ev(t / 1000, 21, 7, -1), ev(((1 << 12) | 9), 1, 7, -1)};
  for (int packet_size : {1, 2, 65536}) {
    ReaderOptions options;
    options.packet_size = packet_size;
    EXPECT_EQ(readAllEvents(path, options), want) << "packet size " << packet_size;
  }
  auto reader = openEventReader(path);
  EventPacket packet;
  while (reader->read(packet)) {
  }
  EXPECT_EQ(reader->stats().trigger_events, 1u);
  EXPECT_EQ(reader->info().width, 64);
  EXPECT_EQ(reader->info().height, 32);
}

TEST(RosbagReader, EventPacketEvt2Payloads) {
  const std::string p = bag::u32(0x80000000u | 2) + bag::u32((1u << 28) | (3u << 22) | (5u << 11) | 6u);
  bag::Chunk chunk{{{3, kT0, bag::eventPacket(640, 480, "evt2", p)}}};
  TempDir dir;
  const std::string path = dir.write("evt2.bag", bag::buildBag({kPackets}, {chunk}));
  EXPECT_EQ(readAllEvents(path), std::vector<Event>{ev((2 << 6) | 3, 5, 6, 1)});
}

TEST(RosbagReader, ReadsThe2014RevisionOfEventArray) {
  // rpg_dvs_ros's dvs_msgs of 2014-15: no header, no size, time as u64 µs; the DVS128's 128x128 unless set.
  const bag::Connection old{0, "/dvs/events", bag::kEventArrayType, bag::kEventArray2014Md5,
                            "Event[] events\n====\nMSG: dvs_msgs/Event\nuint16 x\nuint16 y\nuint64 time\nbool polarity\n"};
  std::vector<bag::DvsEvent> events;
  for (int i = 0; i < 20; ++i) events.push_back({uint16_t(i * 6), uint16_t(127 - i), 5'000'000ull + i * 7000ull, i % 3 == 0});
  const std::vector<bag::DvsEvent> first(events.begin(), events.begin() + 8), rest(events.begin() + 8, events.end());
  TempDir dir;
  const std::string path = dir.write(
      "old.bag", bag::buildBag({old}, {bag::Chunk{{{0, kT0, bag::eventArray2014(first)}, {0, kT0, bag::eventArray2014(rest)}}}}));
  auto reader = openEventReader(path);
  EXPECT_EQ(reader->info().width, 128);
  EXPECT_EQ(reader->info().height, 128);
  const std::vector<Event> got = readAllEvents(path);
  ASSERT_EQ(got.size(), 20u);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(got[i], ev(5000 + i * 7, i * 6, 127 - i, i % 3 == 0 ? 1 : -1)) << i;
  // Another size may be set (the DAVIS240 was used with this revision too); a pixel outside it names the how-to.
  ReaderOptions davis;
  davis.width = 240;
  davis.height = 180;
  davis.size_origin = "--sensor";
  EXPECT_EQ(openEventReader(path, davis)->info().width, 240);
  events[3].x = 128;
  const std::string outside = dir.write("outside.bag", bag::buildBag({old}, {bag::Chunk{{{0, kT0, bag::eventArray2014(events)}}}}));
  const std::string message = errorOf(outside);
  EXPECT_NE(message.find("message 0 of topic /dvs/events: event 3: pixel (128, 124) is outside the 128x128 sensor (size "
                         "from the DVS128 default (the 2014-15 dvs_msgs/EventArray states no size)); set the sensor size"),
            std::string::npos)
      << message;
}

TEST(RosbagReader, TopicChoice) {
  TempDir dir;
  bag::Chunk chunk{{dvsMessage(0, 10), dvsMessage(1000, 5, 2), imuMessage(0)}};
  const std::string two = dir.write("two.bag", bag::buildBag({kDvs, kImu, kDvs2}, {chunk}));
  const std::string message = errorOf(two);
  EXPECT_NE(message.find("the bag has 2 event topics: /dvs/events (dvs_msgs/EventArray, 1 messages), "
                         "/dvs_right/events (dvs_msgs/EventArray, 1 messages); choose one with --topic NAME"),
            std::string::npos)
      << message;
  ReaderOptions right;
  right.topic = "/dvs_right/events";
  const std::vector<Event> events = readAllEvents(two, right);
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events.front(), expected(1000));
  ReaderOptions missing;
  missing.topic = "/nope";
  EXPECT_NE(errorOf(two, missing).find("the bag has no topic '/nope' (--topic); its topics: /dvs/events"),
            std::string::npos);
  ReaderOptions imu;
  imu.topic = "/dvs/imu";
  EXPECT_NE(errorOf(two, imu).find("topic /dvs/imu (--topic) holds sensor_msgs/Imu messages, not events"),
            std::string::npos);

  const std::string none = dir.write("none.bag", bag::buildBag({kImu}, {bag::Chunk{{imuMessage(0), imuMessage(1)}}}));
  EXPECT_NE(errorOf(none).find("the bag has no event topic (of type dvs_msgs/EventArray or "
                               "event_camera_msgs/EventPacket); its topics: /dvs/imu (sensor_msgs/Imu, 2 messages)"),
            std::string::npos)
      << errorOf(none);
}

TEST(RosbagReader, AnEventTopicWithoutMessagesHoldsNoEvents) {
  TempDir dir;
  const std::string path =
      dir.write("empty_topic.bag", bag::buildBag({kDvs, kImu}, {bag::Chunk{{imuMessage(0), imuMessage(1)}}}));
  EXPECT_EQ(errorOf(path), path + ": the event topic /dvs/events has no messages: the file holds no events");
}

// ---------------------------------------------------------------------------------------------------
// Bad input: every case an InputError naming the file, with the byte offset and the message index.

std::string at(const std::string& path, uint64_t offset) { return path + ": byte " + std::to_string(offset) + ": "; }

TEST(RosbagBadInput, TruncatedBag) {
  TempDir dir;
  const std::string full = dvsBag();
  const std::string path = dir.write("cut.bag", full.substr(0, full.size() / 2));
  EXPECT_EQ(errorOf(path).rfind(at(path, 13) + "truncated: the bag header puts the index at byte", 0), 0u)
      << errorOf(path);
  const std::string tiny = dir.write("tiny.bag", full.substr(0, 20));
  EXPECT_EQ(errorOf(tiny).rfind(at(tiny, 13) + "truncated: bag header record", 0), 0u) << errorOf(tiny);
  // The index cut in its middle.
  const std::string index_cut = dir.write("index_cut.bag", full.substr(0, full.size() - 10));
  EXPECT_NE(errorOf(index_cut).find("truncated: chunk info record"), std::string::npos) << errorOf(index_cut);
}

TEST(RosbagBadInput, WrongMagic) {
  TempDir dir;
  std::string bytes = dvsBag();
  bytes[9] = '1';  // "#ROSBAG V1.2"
  bytes[11] = '2';
  const std::string v1 = dir.write("v1.bag", bytes);
  EXPECT_EQ(errorOf(v1), at(v1, 0) + "the version line '#ROSBAG V1.2' names a bag format AsynEVO does not read (only "
                                     "'#ROSBAG V2.0')");
  ReaderOptions forced;
  forced.format = "rosbag";
  const std::string other = dir.write("other.bag", std::string("\x01\x02not a bag at all", 18));
  EXPECT_EQ(errorOf(other, forced), at(other, 0) + "not a ROS bag: the file does not start with '#ROSBAG V2.0' "
                                                   "(truncated, or another format?)");
  EXPECT_EQ(errorOf(dir.write("empty.bag", ""), forced), dir.file("empty.bag") + ": the event file is empty");
}

TEST(RosbagBadInput, CorruptChunks) {
  TempDir dir;
  const std::string good = dvsBag();
  const std::size_t chunk_pos = 13 + 4096;
  // A record length inside the chunk made huge: found, not read past.
  {
    std::string bytes = good;
    const std::size_t header_len = bag::u32(0).size();  // the chunk record: u32 header_len, header, u32 data_len
    const uint32_t chunk_header = static_cast<uint8_t>(bytes[chunk_pos]) | (static_cast<uint8_t>(bytes[chunk_pos + 1]) << 8);
    const std::size_t data = chunk_pos + header_len + chunk_header + 4;  // first record in the chunk
    bytes.replace(data, 4, bag::u32(0x7FFFFFF0));
    const std::string path = dir.write("record.bag", bytes);
    EXPECT_EQ(errorOf(path), at(path, data) + "corrupt record in a chunk: header length 2147483632 runs past the "
                                              "chunk's end");
  }
  // Garbage in an lz4 chunk, and in a bz2 chunk.
  for (const std::string kind : {"lz4", "bz2"}) {
    const std::string bytes = dvsBag([](const std::string& in) { return std::string(in.size() / 3, 'x'); }, kind);
    const std::string path = dir.write(kind + ".bag", bytes);
    EXPECT_EQ(errorOf(path).rfind(at(path, chunk_pos) + "corrupt " + kind + " chunk: ", 0), 0u) << errorOf(path);
  }
  // A stated uncompressed size far above (or below) what the chunk holds: reported, and no buffer of the
  // stated size is allocated up front.
  for (const std::string kind : {"lz4", "bz2"}) {
    std::string bytes = kind == "lz4" ? dvsBag(bag::lz4, "lz4") : dvsBag(bag::bz2, "bz2");
    const std::size_t size_field = bytes.find("size=", chunk_pos) + 5;
    bytes.replace(size_field, 4, bag::u32(200u << 20));
    const std::string big = dir.write(kind + "_big.bag", bytes);
    EXPECT_NE(errorOf(big).find("corrupt " + kind + " chunk: "), std::string::npos) << errorOf(big);
    EXPECT_NE(errorOf(big).find("bytes instead of the stated 209715200"), std::string::npos) << errorOf(big);
    bytes.replace(size_field, 4, bag::u32(100));
    const std::string small = dir.write(kind + "_small.bag", bytes);
    EXPECT_EQ(errorOf(small), at(small, chunk_pos) + "corrupt " + kind + " chunk: it decompresses to more than the "
                                                      "chunk's stated size");
  }
  // An unknown compression.
  {
    const std::string bytes = dvsBag([](const std::string& in) { return in; }, "zip");
    const std::string path = dir.write("zip.bag", bytes);
    EXPECT_EQ(errorOf(path), at(path, chunk_pos) + "chunk compression 'zip' is not one of none, bz2, lz4");
  }
  // Two chunk info records for one chunk (its events would be read twice).
  {
    std::string bytes = good;
    const std::size_t first = bytes.rfind(bag::u64(chunk_pos));
    const std::size_t second = bytes.find("chunk_pos=", first + 8) + 10;
    ASSERT_NE(second, std::string::npos + 10);
    bytes.replace(second, 8, bag::u64(chunk_pos));
    const std::string path = dir.write("twice.bag", bytes);
    EXPECT_NE(errorOf(path).find("corrupt index: two chunk info records for the chunk at byte 4109"), std::string::npos)
        << errorOf(path);
  }
  // A chunk info pointing into the middle of a record.
  {
    std::string bytes = good;
    const std::size_t pos = bytes.rfind(bag::u64(chunk_pos));
    ASSERT_NE(pos, std::string::npos);
    bytes.replace(pos, 8, bag::u64(chunk_pos + 1));
    const std::string path = dir.write("pos.bag", bytes);
    EXPECT_EQ(errorOf(path).rfind(at(path, chunk_pos + 1) + "corrupt", 0), 0u) << errorOf(path);
  }
}

TEST(RosbagBadInput, MalformedMessages) {
  TempDir dir;
  // The events array claims more elements than the message holds.
  {
    std::string m = bag::eventArray(240, 180, dvsEvents(0, 3));
    m.replace(m.size() - 3 * 13 - 4, 4, bag::u32(1000));
    const std::string path = dir.write("array.bag", bag::buildBag({kDvs}, {bag::Chunk{{dvsMessage(0, 2), {0, kT0, m}}}}));
    const std::string message = errorOf(path);
    EXPECT_NE(message.find(": message 1 of topic /dvs/events: malformed message: 1000 events of 13 bytes need 13000 "
                           "bytes, the message has 39 left after its header"),
              std::string::npos)
        << message;
  }
  // A message cut inside its header's frame_id.
  {
    const std::string m = bag::u32(0) + bag::rosTime(0) + bag::u32(50) + "cam";
    const std::string path = dir.write("header.bag", bag::buildBag({kDvs}, {bag::Chunk{{{0, kT0, m}}}}));
    EXPECT_NE(errorOf(path).find("message 0 of topic /dvs/events: malformed message: the header's frame_id needs 50 "
                                 "bytes at byte 16 but the message has only 19 bytes"),
              std::string::npos)
        << errorOf(path);
  }
  // An EventPacket whose payload length runs past the message, an unknown encoding, big-endian data.
  {
    std::string m = bag::eventPacket(640, 480, "evt3", "abcd");
    m.replace(m.size() - 8, 4, bag::u32(99));
    const std::string path = dir.write("payload.bag", bag::buildBag({kPackets}, {bag::Chunk{{{3, kT0, m}}}}));
    EXPECT_NE(errorOf(path).find("malformed message: an events payload of 99 bytes, but the message has 4 left"),
              std::string::npos)
        << errorOf(path);
    const std::string mono = dir.write(
        "mono.bag", bag::buildBag({kPackets}, {bag::Chunk{{{3, kT0, bag::eventPacket(640, 480, "mono", "ab")}}}}));
    EXPECT_NE(errorOf(mono).find("encoding 'mono' is not decoded by AsynEVO (supported: evt3, evt2)"),
              std::string::npos);
    const std::string big = dir.write(
        "big.bag", bag::buildBag({kPackets}, {bag::Chunk{{{3, kT0, bag::eventPacket(640, 480, "evt3", "ab", 0, true)}}}}));
    EXPECT_NE(errorOf(big).find("is_bigendian is set"), std::string::npos);
  }
  // Another revision of the message type (another MD5 sum).
  {
    bag::Connection old = kDvs;
    old.md5 = "e952962d6467a2934a8b913c51f1bc4f";
    const std::string path = dir.write("md5.bag", bag::buildBag({old}, {bag::Chunk{{dvsMessage(0, 2)}}}));
    EXPECT_NE(errorOf(path).find("topic /dvs/events has a revision of dvs_msgs/EventArray with MD5 sum "
                                 "'e952962d6467a2934a8b913c51f1bc4f'; AsynEVO reads the revision with MD5 sum "
                                 "5e8beee5a6c107e504c2e78903c224b8"),
              std::string::npos)
        << errorOf(path);
  }
}

TEST(RosbagBadInput, UnsortedTimeAndPixelsOutsideTheSensor) {
  TempDir dir;
  {
    std::vector<bag::DvsEvent> events = dvsEvents(0, 5);
    events[3].t_ns -= 10'000;  // 10 µs back
    const std::string path = dir.write(
        "time.bag", bag::buildBag({kDvs}, {bag::Chunk{{dvsMessage(100, 1), {0, kT0, bag::eventArray(240, 180, events)}}}}));
    // Message 1's first event is already earlier than message 0's.
    const std::string message = errorOf(path);
    EXPECT_NE(message.find("message 1 of topic /dvs/events: event 0: time goes backwards by 100000 ns"),
              std::string::npos)
        << message;
    ReaderOptions tolerant;
    tolerant.max_time_reversal_ns = 200'000;
    EXPECT_EQ(readAllEvents(path, tolerant).size(), 6u);
  }
  {
    std::vector<bag::DvsEvent> events = dvsEvents(0, 5);
    events[2].x = 240;
    const std::string path =
        dir.write("pixel.bag", bag::buildBag({kDvs}, {bag::Chunk{{{0, kT0, bag::eventArray(240, 180, events)}}}}));
    const std::string message = errorOf(path);
    EXPECT_NE(message.find("message 0 of topic /dvs/events: event 2: pixel (240, 2) is outside the 240x180 sensor "
                           "(size from the bag's messages)"),
              std::string::npos)
        << message;
  }
  {
    // A later message stating another size.
    const std::string path = dir.write(
        "size.bag", bag::buildBag({kDvs}, {bag::Chunk{{dvsMessage(0, 2), {0, kT0, bag::eventArray(346, 260, dvsEvents(2, 2))}}}}));
    EXPECT_NE(errorOf(path).find("message 1 of topic /dvs/events: the message states a 346x260 sensor, the topic's "
                                 "first message 240x180"),
              std::string::npos)
        << errorOf(path);
  }
}

TEST(RosbagBadInput, ConfiguredSizeMustAgreeWithTheMessages) {
  TempDir dir;
  const std::string path = dir.write("events.bag", dvsBag());
  ReaderOptions options;
  options.width = 346;
  options.height = 260;
  options.size_origin = "--sensor";
  EXPECT_NE(errorOf(path, options).find("message 0 of topic /dvs/events: sensor size 240x180 in the message differs "
                                        "from 346x260 set by --sensor"),
            std::string::npos)
      << errorOf(path, options);
  options.width = 240;
  options.height = 180;
  EXPECT_EQ(readAllEvents(path, options).size(), 350u);
}

TEST(RosbagBadInput, UnindexedBag) {
  TempDir dir;
  std::string bytes = dvsBag();
  const std::size_t pos = bytes.find("index_pos=") + 10;
  bytes.replace(pos, 8, bag::u64(0));
  const std::string path = dir.write("open.bag", bytes);
  EXPECT_EQ(errorOf(path), at(path, 13) + "the bag has no index (its recording was not closed properly); rebuild it "
                                          "with 'rosbag reindex'");
}

TEST(RosbagBadInput, EveryTruncationFailsCleanly) {
  // Whatever the cut, an InputError (never a crash or a silent short read).
  TempDir dir;
  const std::string full = dvsBag(bag::lz4, "lz4");
  for (std::size_t n = 1; n < full.size(); n += 97) {
    const std::string path = dir.write("cut.bag", full.substr(0, n));
    ReaderOptions forced;
    forced.format = "rosbag";
    EXPECT_NE(errorOf(path, forced), "") << "cut at " << n;
  }
}

}  // namespace
}  // namespace asynevo
