// AEDAT 4.0 reader.
//
// Two kinds of input:
// - the two real recordings of ../shared/data/formats/aedat4 (a DVXplorer recording, GPL-3.0, and a trimmed
//   DAVIS346 recording with frames), not copied into the repository; expected values from
//   ../shared/data/SOURCES.md. The tests skip when the folder is missing.
// - files built byte by byte from the published specification (aedat4_fixture.hpp): every compression, the
//   data table, packets of skipped and counted streams, and each kind of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "aedat4_fixture.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::errorOf;
using testing::ev;
using testing::expectErrorAt;
using testing::TempDir;
namespace fx = testing::aedat4;

std::string sample(const std::string& name) { return std::string(ASYNEVO_SHARED_DATA_DIR) + "/formats/aedat4/" + name; }

#define SKIP_WITHOUT_SAMPLE(path)                                                                               \
  if (!std::filesystem::exists(path))                                                                           \
  GTEST_SKIP() << "sample recording " << (path) << " not found: the shared data folder (../shared/data beside " \
                  "the repository) is missing; these files are not copied into the repository"

const ContainerStream* streamWithId(const ReaderStats& stats, int id) {
  for (const ContainerStream& s : stats.streams) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

// ---------------------------------------------------------------------------------------------------
// Real recordings

TEST(Aedat4Samples, DvxplorerRecordingMatchesItsSourceFigures) {
  const std::string path = sample("sample.aedat4");
  SKIP_WITHOUT_SAMPLE(path);
  auto reader = openEventReader(path);  // auto: detected by its version line
  EXPECT_EQ(reader->info().format, "aedat4");
  EXPECT_EQ(reader->info().width, 320);
  EXPECT_EQ(reader->info().height, 240);
  EventPacket packet;
  uint64_t count = 0, on = 0;
  Event first{}, last{};
  bool sorted = true;
  while (reader->read(packet)) {
    for (const Event& e : packet.events) {
      if (count == 0) first = e;
      if (count > 0 && e.t_ns < last.t_ns) sorted = false;
      last = e;
      ++count;
      on += e.polarity > 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(count, 111954u);
  EXPECT_EQ(on, 55023u);
  EXPECT_TRUE(sorted);
  EXPECT_EQ(first.t_ns, 1605537493718345LL * 1000);
  EXPECT_EQ(first.x, 154);
  EXPECT_EQ(first.y, 204);
  EXPECT_EQ(first.polarity, -1);
  EXPECT_EQ(last.t_ns, 1605537494308262LL * 1000);
  EXPECT_EQ(last.x, 88);
  EXPECT_EQ(last.y, 237);
  EXPECT_EQ(last.polarity, 1);
  const ReaderStats& stats = reader->stats();
  EXPECT_EQ(stats.events, 111954u);
  EXPECT_EQ(stats.imu_samples, 475u);
  EXPECT_EQ(stats.trigger_events, 0u);
  ASSERT_EQ(stats.streams.size(), 3u);
  const int ids[] = {0, 2, 3};
  const char* types[] = {"EVTS", "IMUS", "TRIG"};
  const uint64_t packets[] = {59, 59, 0};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(stats.streams[i].id, ids[i]);
    EXPECT_EQ(stats.streams[i].type, types[i]);
    EXPECT_EQ(stats.streams[i].packets, packets[i]) << types[i];
  }
  EXPECT_TRUE(stats.streams[0].delivered);
  EXPECT_EQ(stats.streams[0].name, "events");
}

TEST(Aedat4Samples, Davis346RecordingSkipsFramesAndCountsImuAndTriggers) {
  const std::string path = sample("sample_davis346_trimmed.aedat4");
  SKIP_WITHOUT_SAMPLE(path);
  ReaderOptions options;
  options.format = "aedat4";
  options.packet_size = 1000;  // several reads per AEDAT packet and AEDAT packets per read
  auto reader = openEventReader(path, options);
  EXPECT_EQ(reader->info().width, 346);
  EXPECT_EQ(reader->info().height, 260);
  EventPacket packet;
  uint64_t count = 0, on = 0;
  int64_t first_t = 0, last_t = 0;
  int max_x = 0, max_y = 0;
  while (reader->read(packet)) {
    EXPECT_EQ(packet.first_index, count);
    for (const Event& e : packet.events) {
      if (count == 0) first_t = e.t_ns;
      EXPECT_GE(e.t_ns, last_t);
      last_t = e.t_ns;
      ++count;
      on += e.polarity > 0 ? 1 : 0;
      max_x = std::max<int>(max_x, e.x);
      max_y = std::max<int>(max_y, e.y);
    }
  }
  EXPECT_EQ(count, 6676u);
  EXPECT_EQ(on, 3563u);
  EXPECT_EQ(max_x, 334);
  EXPECT_EQ(max_y, 245);
  EXPECT_EQ(first_t, 1589163147368868LL * 1000);
  EXPECT_EQ(last_t, 1589163147538809LL * 1000);
  const ReaderStats& stats = reader->stats();
  EXPECT_EQ(stats.imu_samples, 160u);
  EXPECT_EQ(stats.trigger_events, 17u);
  ASSERT_EQ(stats.streams.size(), 4u);
  const char* types[] = {"EVTS", "FRME", "IMUS", "TRIG"};
  const uint64_t packets[] = {17, 4, 16, 13};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(stats.streams[i].id, i);
    EXPECT_EQ(stats.streams[i].type, types[i]);
    EXPECT_EQ(stats.streams[i].packets, packets[i]) << types[i];
  }
  EXPECT_EQ(stats.streams[1].width, 346);  // the frame stream's geometry is listed too
}

// ---------------------------------------------------------------------------------------------------
// Files built from the specification

const std::vector<fx::StreamSpec> kStreams = {
    {1, "EVTS", "events", 64, 32}, {2, "IMUS", "imu"}, {5, "FRME", "frames", 64, 32}, {7, "TRIG", "triggers"}};

// The file: version line, IOHeader, the packets (payloads compressed as `compression` says) and, when
// `with_table`, a stand-in data table whose position the IOHeader gives.
std::string buildFile(int32_t compression, const std::vector<std::pair<int, std::string>>& packets,
                      bool with_table = true, const std::vector<fx::StreamSpec>& streams = kStreams) {
  const std::string xml = fx::infoXml(streams);
  std::string body;
  for (const auto& [stream, payload] : packets) body += fx::packet(stream, fx::compress(payload, compression));
  const int64_t table = static_cast<int64_t>(fx::kMagic.size() + fx::ioHeader(compression, -1, xml).size() + body.size());
  std::string file = fx::kMagic + fx::ioHeader(compression, with_table ? table : -1, xml) + body;
  if (with_table) file += "a FileDataTable FlatBuffer would be here; the reader stops before it";
  return file;
}

std::vector<std::pair<int, std::string>> standardPackets() {
  return {{1, fx::eventPacket({{1000, 1, 2, 1}, {1000, 3, 4, 0}, {1500, 63, 31, 1}})},
          {2, fx::imuPacket(2, 1200)},
          {5, "frames are skipped unread, so this need not be a Frame FlatBuffer"},
          {1, fx::eventPacket({{2000, 10, 11, 0}, {2500, 12, 13, 1}})},
          {1, fx::eventPacket({})},
          {2, fx::imuPacket(3, 2600)}};
}

TEST(Aedat4Reader, ReadsEveryCompressionOfTheSpecification) {
  TempDir dir;
  const std::vector<Event> expected = {ev(1000, 1, 2, 1), ev(1000, 3, 4, -1), ev(1500, 63, 31, 1), ev(2000, 10, 11, -1),
                                       ev(2500, 12, 13, 1)};
  for (const int32_t compression : {fx::kNone, fx::kLz4, fx::kLz4High, fx::kZstd, fx::kZstdHigh}) {
    for (const bool with_table : {true, false}) {
      SCOPED_TRACE("compression " + std::to_string(compression) + (with_table ? ", with data table" : ", no table"));
      const auto path = dir.write("rec.aedat4", buildFile(compression, standardPackets(), with_table));
      ReaderOptions options;
      options.packet_size = 2;  // reads that end inside an AEDAT packet
      auto reader = openEventReader(path, options);
      EXPECT_EQ(reader->info().format, "aedat4");
      EXPECT_EQ(reader->info().width, 64);
      EXPECT_EQ(reader->info().height, 32);
      std::vector<Event> events;
      EventPacket packet;
      while (reader->read(packet)) {
        EXPECT_LE(packet.size(), 2u);
        events.insert(events.end(), packet.events.begin(), packet.events.end());
      }
      ASSERT_EQ(events.size(), expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(events[i].t_ns, expected[i].t_ns) << i;
        EXPECT_EQ(events[i].x, expected[i].x) << i;
        EXPECT_EQ(events[i].y, expected[i].y) << i;
        EXPECT_EQ(events[i].polarity, expected[i].polarity) << i;
      }
      const ReaderStats& stats = reader->stats();
      EXPECT_EQ(stats.imu_samples, 5u);
      EXPECT_EQ(streamWithId(stats, 1)->packets, 3u);
      EXPECT_EQ(streamWithId(stats, 1)->elements, 5u);
      EXPECT_TRUE(streamWithId(stats, 1)->delivered);
      EXPECT_EQ(streamWithId(stats, 2)->packets, 2u);
      EXPECT_EQ(streamWithId(stats, 2)->elements, 5u);
      EXPECT_EQ(streamWithId(stats, 5)->packets, 1u);
      EXPECT_EQ(streamWithId(stats, 5)->type, "FRME");
      EXPECT_EQ(streamWithId(stats, 7)->packets, 0u);
    }
  }
}

TEST(Aedat4Reader, SensorSizeFromTheFileElseConfiguredElseTheEvents) {
  TempDir dir;
  auto path = dir.write("rec.aedat4", buildFile(fx::kLz4, standardPackets()));
  ReaderOptions options;
  options.width = 64;
  options.height = 32;
  EXPECT_EQ(readAllEvents(path, options).size(), 5u);  // the same size as the file's: accepted
  options.width = 640;
  options.height = 480;
  expectErrorAt(path, 18, "sensor size 64x32 in the file (event stream 1) differs from 640x480 set by the reader options",
                  options);

  const std::vector<fx::StreamSpec> unsized = {{0, "EVTS", "events"}};
  path = dir.write("unsized.aedat4", buildFile(fx::kNone, {{0, fx::eventPacket({{5, 9, 4, 1}, {6, 2, 7, 0}})}}, true,
                                               unsized));
  EXPECT_EQ(openEventReader(path, options)->info().width, 640);  // configured
  auto reader = openEventReader(path);                            // neither: the events' bounding box
  EXPECT_EQ(reader->info().width, 10);
  EXPECT_EQ(reader->info().height, 8);
  EXPECT_EQ(readAllEvents(path).size(), 2u);
}

TEST(Aedat4Reader, AutoDetectionByTheVersionLine) {
  TempDir dir;
  const auto path = dir.write("recording.bin", buildFile(fx::kZstd, standardPackets()));
  EXPECT_EQ(openEventReader(path)->info().format, "aedat4");
  const auto aedat3 = dir.write("old.aedat", "#!AER-DAT3.1\r\n#Format: RAW\r\n#End Of ASCII Header\r\n");
  const std::string message = errorOf(aedat3);
  EXPECT_EQ(message, aedat3 + ": byte 0: the version line '#!AER-DAT3.1' names an AEDAT version AsynEVO does not "
                              "read (only AEDAT 4.0, '#!AER-DAT4.0')");
}

// Some writers align a FlatBuffer's 8-byte fields relative to the buffer after the size prefix, not to the
// prefix as DV does (the trimmed DAVIS346 sample is one). Four bytes inserted after the IOHeader's file
// identifier give that layout: the int64 dataTablePosition is then 8-byte aligned only from byte 4.
TEST(Aedat4Reader, ReadsFlatBuffersAlignedAfterTheSizePrefix) {
  TempDir dir;
  const std::string body = fx::packet(1, fx::eventPacket({{7, 1, 2, 1}}));
  const std::string xml = fx::infoXml(kStreams);
  std::string header = fx::ioHeader(fx::kNone, -1, xml);
  const auto table = static_cast<int64_t>(fx::kMagic.size() + header.size() + 4 + body.size());
  header = fx::ioHeader(fx::kNone, table, xml);
  header.insert(12, 4, '\0');
  header.replace(0, 4, fx::le32(static_cast<uint32_t>(header.size() - 4)));
  header.replace(4, 4, fx::le32(24));  // the root offset, 4 bytes further
  const auto path = dir.write("shifted.aedat4", fx::kMagic + header + body + "TABLE");
  const std::vector<Event> events = readAllEvents(path);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].t_ns, 7000);
  EXPECT_EQ(events[0].x, 1);
  EXPECT_EQ(events[0].y, 2);
}

// ---------------------------------------------------------------------------------------------------
// Bad input: each names the file and the byte offset.

TEST(Aedat4Reader, BadHeaders) {
  TempDir dir;
  ReaderOptions aedat4;
  aedat4.format = "aedat4";
  const std::string good = buildFile(fx::kNone, standardPackets());
  const std::string xml = fx::infoXml(kStreams);

  auto path = dir.write("magic.aedat4", "#!AER-DAT4.1\r\n" + good.substr(14));
  expectErrorAt(path, 0, "not an AEDAT 4.0 file: it does not start with the version line '#!AER-DAT4.0\\r\\n' "
                           "(it starts with '#!AER-DAT4.1')", aedat4);
  path = dir.write("short.aedat4", good.substr(0, 16));
  expectErrorAt(path, 14, "truncated: the file ends before the IOHeader size", aedat4);
  path = dir.write("cut.aedat4", good.substr(0, 100));
  expectErrorAt(path, 18, "truncated: the IOHeader has 82 of its", aedat4);

  std::string header = fx::ioHeader(fx::kNone, -1, xml);
  header[7] = '\x7F';  // the root offset points far outside the FlatBuffer
  path = dir.write("root.aedat4", fx::kMagic + header);
  expectErrorAt(path, 18, "the IOHeader FlatBuffer fails verification", aedat4);
  header = fx::ioHeader(fx::kNone, -1, xml);
  header[44] = '\xFF';  // the info node string's length reaches past the buffer
  path = dir.write("string.aedat4", fx::kMagic + header);
  expectErrorAt(path, 18, "the IOHeader FlatBuffer fails verification", aedat4);

  path = dir.write("compression.aedat4", fx::kMagic + fx::ioHeader(7, -1, xml));
  expectErrorAt(path, 18, "unknown compression type 7 in the IOHeader (known: 0 none, 1 LZ4, 2 LZ4 high, 3 Zstd, "
                            "4 Zstd high)");
  path = dir.write("table.aedat4", fx::kMagic + fx::ioHeader(fx::kNone, 1'000'000, xml));
  const auto size = std::filesystem::file_size(path);
  expectErrorAt(path, size, "truncated: the file ends at byte " + std::to_string(size) +
                                  ", before the data table the IOHeader places at byte 1000000");
  path = dir.write("noevents.aedat4", fx::kMagic + fx::ioHeader(fx::kNone, -1, fx::infoXml({{2, "IMUS", "imu"}})));
  expectErrorAt(path, 18, "no event stream: the IOHeader's info node lists the streams 2 IMUS, none with "
                            "typeIdentifier EVTS");
  path = dir.write("xml.aedat4", fx::kMagic + fx::ioHeader(fx::kNone, -1, "<dv><node name=\"outInfo\"><attr key=\"x\""));
  EXPECT_NE(errorOf(path).find("IOHeader info node: unterminated tag"), std::string::npos) << errorOf(path);
  path = dir.write("sizex.aedat4", fx::kMagic + fx::ioHeader(fx::kNone, -1, fx::infoXml({{0, "EVTS", "e", 70000, 5}})));
  EXPECT_NE(errorOf(path).find("IOHeader info node: sizeX '70000' is not a sensor dimension in 1..32767"),
            std::string::npos)
      << errorOf(path);
}

// Offset of the first packet in files made by buildFile with kStreams.
uint64_t firstPacketOffset() { return 14 + fx::ioHeader(fx::kNone, -1, fx::infoXml(kStreams)).size(); }

TEST(Aedat4Reader, TruncatedAndCorruptPackets) {
  TempDir dir;
  const uint64_t start = firstPacketOffset();
  const std::string events = fx::eventPacket({{1000, 1, 2, 1}, {1001, 3, 4, 0}});
  const uint64_t second = start + 8 + events.size();

  // The file ends inside the second packet's payload, and inside a packet header.
  std::string file = buildFile(fx::kNone, {{1, events}, {1, events}}, false);
  auto path = dir.write("payload.aedat4", file.substr(0, file.size() - 5));
  expectErrorAt(path, second, "truncated: packet 1 (stream 1, EVTS) declares " + std::to_string(events.size()) +
                                    " bytes, only " + std::to_string(events.size() - 5) + " remain at the end of the file");
  path = dir.write("header.aedat4", file.substr(0, second + 3));
  expectErrorAt(path, second, "truncated: the 3 bytes at the end of the file are not a whole packet header");
  // The IOHeader places the data table 4 bytes into the first packet's payload.
  path = dir.write("table.aedat4", fx::kMagic + fx::ioHeader(fx::kNone, static_cast<int64_t>(start + 12),
                                                             fx::infoXml(kStreams)) + fx::packet(1, events));
  expectErrorAt(path, start, "truncated: packet 0 (stream 1, EVTS) declares " + std::to_string(events.size()) +
                                   " bytes, only 4 remain before the data table");

  // Packet headers: a stream the info node does not list, a negative size.
  path = dir.write("stream.aedat4", buildFile(fx::kNone, {{1, events}, {9, events}}));
  expectErrorAt(path, second, "packet 1 belongs to stream 9, which the IOHeader's info node does not list "
                                "(streams: 1 EVTS, 2 IMUS, 5 FRME, 7 TRIG");
  file = buildFile(fx::kNone, {{1, events}, {1, events}}, false);
  file.replace(second + 4, 4, fx::le32(0xFFFFFFF0u));
  path = dir.write("negative.aedat4", file);
  expectErrorAt(path, second, "packet 1 (stream 1, EVTS): negative size -16");

  // Corrupt FlatBuffers: a size prefix that disagrees, a vector longer than the packet, a bad root offset.
  std::string bad = events;
  bad[0] = '\x10';
  path = dir.write("prefix.aedat4", buildFile(fx::kNone, {{1, bad}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS): the EventPacket FlatBuffer's size prefix says 16 bytes");
  bad = events;
  bad.replace(28, 4, fx::le32(1000));  // the vector claims 1000 events
  path = dir.write("vector.aedat4", buildFile(fx::kLz4, {{1, bad}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS): the EventPacket FlatBuffer fails verification");
  bad = fx::imuPacket(2, 5);
  bad.replace(4, 4, fx::le32(0x7FFFFFF0u));
  path = dir.write("imu.aedat4", buildFile(fx::kZstd, {{2, bad}}));
  expectErrorAt(path, start, "packet 0 (stream 2, IMUS): the IMUPacket FlatBuffer fails verification");
  path = dir.write("tiny.aedat4", buildFile(fx::kNone, {{1, "abc"}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS): the packet has 3 bytes, too few for a size-prefixed "
                               "EventPacket FlatBuffer");
}

TEST(Aedat4Reader, DecompressionErrors) {
  TempDir dir;
  const uint64_t start = firstPacketOffset();
  const std::string events = fx::eventPacket({{1000, 1, 2, 1}, {1001, 3, 4, 0}});
  for (const int32_t compression : {fx::kLz4, fx::kZstd}) {
    const std::string name = compression == fx::kLz4 ? "LZ4" : "Zstd";
    const std::string frame = fx::compress(events, compression);
    auto file = [&](const std::string& payload) {
      std::string f = buildFile(compression, {}, false);
      return f + fx::packet(1, payload);
    };
    auto path = dir.write("cut.aedat4", file(frame.substr(0, frame.size() - 3)));
    EXPECT_NE(errorOf(path).find(": byte " + std::to_string(start) + ": packet 0 (stream 1, EVTS): " + name + " frame: "),
              std::string::npos)
        << errorOf(path);
    path = dir.write("magic.aedat4", file("XXXX" + frame.substr(4)));
    EXPECT_NE(errorOf(path).find(": byte " + std::to_string(start) + ": packet 0 (stream 1, EVTS): " + name + " frame: "),
              std::string::npos)
        << errorOf(path);
    path = dir.write("trailing.aedat4", file(frame + "xyz"));
    expectErrorAt(path, start, "packet 0 (stream 1, EVTS): " + name + " frame: 3 bytes follow the end of the frame");
  }
}

TEST(Aedat4Reader, UnsortedTimesAndPixelsOutsideTheSensor) {
  TempDir dir;
  const uint64_t start = firstPacketOffset();
  const std::string first = fx::eventPacket({{1000, 1, 2, 1}});
  const uint64_t second = start + 8 + fx::compress(first, fx::kLz4).size();
  auto path = dir.write("time.aedat4", buildFile(fx::kLz4, {{1, first}, {1, fx::eventPacket({{1000, 1, 1, 1}, {900, 1, 1, 1}})}}));
  expectErrorAt(path, second, "packet 1 (stream 1, EVTS), event 1: time goes backwards by 100000 ns");
  ReaderOptions tolerant;
  tolerant.max_time_reversal_ns = 200'000;
  EXPECT_EQ(readAllEvents(path, tolerant).size(), 3u);
  path = dir.write("x.aedat4", buildFile(fx::kLz4, {{1, fx::eventPacket({{1000, 64, 3, 1}})}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS), event 0: pixel (64, 3) is outside the 64x32 sensor");
  path = dir.write("y.aedat4", buildFile(fx::kNone, {{1, fx::eventPacket({{1000, 3, -1, 1}})}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS), event 0: pixel (3, -1) is outside the 64x32 sensor");
  path = dir.write("p.aedat4", buildFile(fx::kNone, {{1, fx::eventPacket({{1000, 3, 1, 2}})}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS), event 0: polarity 2 is not one of 0, 1, -1");
  path = dir.write("t.aedat4", buildFile(fx::kNone, {{1, fx::eventPacket({{INT64_MAX / 100, 3, 1, 1}})}}));
  expectErrorAt(path, start, "packet 0 (stream 1, EVTS), event 0: time " + std::to_string(INT64_MAX / 100) +
                                   " µs is out of range");
}

}  // namespace
}  // namespace asynevo
