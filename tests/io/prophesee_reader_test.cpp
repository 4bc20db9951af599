// Prophesee RAW (EVT 3.0, EVT 2.0) and DAT readers.
//
// Two kinds of input:
// - real recordings from the formats' own ecosystem, read from the shared data folder beside the
//   repository (../shared/data/formats; several are GPL, so they are not copied here). Expected values
//   are those of ../shared/data/SOURCES.md. The tests skip when the folder is missing.
// - small files built byte by byte in the tests from the published bit layouts (Prophesee's "EVT 3.0
//   Format", "EVT 2.0 Format", "DAT File Format" and "RAW File Format" pages), not with any AsynEVO
//   writer: every word kind, vectors split across packets, time wrap-around, and each kind of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <initializer_list>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::errorOf;
using testing::ev;
using testing::expectErrorAt;
using testing::TempDir;

// ---------------------------------------------------------------------------------------------------
// Byte builders (little-endian, as the formats are written by default).

std::string le16(uint32_t w) { return {static_cast<char>(w & 0xFF), static_cast<char>((w >> 8) & 0xFF)}; }
std::string le32(uint32_t w) { return le16(w & 0xFFFF) + le16(w >> 16); }

// EVT 3.0 words: 4-bit type in bits 15..12.
uint32_t addrY(uint32_t y) { return 0x0000 | y; }
uint32_t addrX(uint32_t x, uint32_t p) { return 0x2000 | (p << 11) | x; }
uint32_t vectBaseX(uint32_t x, uint32_t p) { return 0x3000 | (p << 11) | x; }
uint32_t vect12(uint32_t mask) { return 0x4000 | mask; }
uint32_t vect8(uint32_t mask) { return 0x5000 | mask; }
uint32_t timeLow(uint32_t t) { return 0x6000 | t; }
uint32_t timeHigh(uint32_t t) { return 0x8000 | t; }

std::string evt3Words(std::initializer_list<uint32_t> words) {
  std::string bytes;
  for (const uint32_t w : words) bytes += le16(w);
  return bytes;
}

// EVT 2.0 words: 4-bit type in bits 31..28.
uint32_t cd(uint32_t p, uint32_t t_low, uint32_t x, uint32_t y) { return (p << 28) | (t_low << 22) | (x << 11) | y; }
uint32_t timeHigh2(uint32_t t) { return 0x80000000u | t; }

std::string evt2Words(std::initializer_list<uint32_t> words) {
  std::string bytes;
  for (const uint32_t w : words) bytes += le32(w);
  return bytes;
}

// DAT record: uint32 time (µs), uint32 x | y << 14 | p << 28.
std::string datRecord(uint32_t t, uint32_t x, uint32_t y, uint32_t p) { return le32(t) + le32(x | (y << 14) | (p << 28)); }

const std::string kEvt3Header = "% date 2024-01-01 00:00:00\n% evt 3.0\n% format EVT3;height=32;width=64\n% geometry 64x32\n% end\n";
const std::string kEvt2Header = "% date 2024-01-01 00:00:00\n% evt 2.0\n% width 640\n% height 480\n";
const std::string kDatHeader = "% Data file containing CD events\n% Date 2020-09-14 14:18:29\n% Version 2\n% Width 640\n% Height 480\n";
const std::string kDatCdTypeSize = std::string("\x0C\x08", 2);

ReaderOptions withPacketSize(int n) {
  ReaderOptions options;
  options.packet_size = n;
  return options;
}

// ---------------------------------------------------------------------------------------------------
// Real recordings (../shared/data/formats; see ../shared/data/SOURCES.md).

std::string sample(const std::string& relative) { return std::string(ASYNEVO_SHARED_DATA_DIR) + "/formats/" + relative; }

#define SKIP_WITHOUT(path)                                                                                      \
  if (!std::filesystem::exists(path))                                                                           \
  GTEST_SKIP() << "sample recording " << (path) << " not found: the shared data folder (../shared/data beside " \
                  "the repository) is missing; these GPL files are not copied into the repository"

struct Summary {
  uint64_t events = 0;
  uint64_t on = 0;
  Event first;
  Event last;
  bool sorted = true;
  int min_x = INT_MAX, max_x = -1, min_y = INT_MAX, max_y = -1;
};

Summary summarize(EventReader& reader) {
  Summary s;
  EventPacket packet;
  while (reader.read(packet)) {
    for (const Event& e : packet.events) {
      if (s.events == 0) s.first = e;
      if (s.events > 0 && e.t_ns < s.last.t_ns) s.sorted = false;
      s.last = e;
      ++s.events;
      s.on += e.polarity > 0 ? 1 : 0;
      s.min_x = std::min<int>(s.min_x, e.x);
      s.max_x = std::max<int>(s.max_x, e.x);
      s.min_y = std::min<int>(s.min_y, e.y);
      s.max_y = std::max<int>(s.max_y, e.y);
    }
  }
  return s;
}

TEST(PropheseeSamples, Evt3RecordingMatchesItsSourceFigures) {
  const std::string path = sample("evt3/evt3_sample.raw");
  SKIP_WITHOUT(path);
  auto reader = openEventReader(path);  // format auto
  EXPECT_EQ(reader->info().format, "evt3");
  // No geometry line; plugin_name hal_plugin_gen41_evk3 is the 1280x720 Gen4.1 sensor.
  EXPECT_EQ(reader->info().width, 1280);
  EXPECT_EQ(reader->info().height, 720);
  const Summary s = summarize(*reader);
  EXPECT_EQ(s.events, 219596u);
  EXPECT_EQ(s.on, 115532u);
  EXPECT_EQ(s.first, ev(11718656, 874, 200, -1));
  EXPECT_EQ(s.last, ev(11727457, 1218, 572, 1));
  EXPECT_TRUE(s.sorted);
  EXPECT_EQ(s.min_x, 0);
  EXPECT_EQ(s.max_x, 1279);
  EXPECT_EQ(s.min_y, 0);
  EXPECT_EQ(s.max_y, 719);
  EXPECT_EQ(reader->stats().events, 219596u);
  EXPECT_EQ(reader->stats().trigger_events, 0u);
  EXPECT_EQ(reader->stats().clamped_times, 0u);
}

TEST(PropheseeSamples, Evt3PacketSizeDoesNotChangeTheEvents) {
  const std::string path = sample("evt3/evt3_sample.raw");
  SKIP_WITHOUT(path);
  const auto whole = readAllEvents(path);
  for (const int packet_size : {1, 5, 12, 1000}) {  // small packets split the 8- and 12-event vectors
    EXPECT_EQ(readAllEvents(path, withPacketSize(packet_size)), whole) << "packet size " << packet_size;
  }
}

TEST(PropheseeSamples, Evt2RecordingMatchesItsSourceFigures) {
  const std::string path = sample("evt2/evt2_sample.raw");
  SKIP_WITHOUT(path);
  auto reader = openEventReader(path);
  EXPECT_EQ(reader->info().format, "evt2");
  EXPECT_EQ(reader->info().width, 640);  // hal_plugin_gen3_fx3: Gen3 VGA
  EXPECT_EQ(reader->info().height, 480);
  const Summary s = summarize(*reader);
  EXPECT_EQ(s.events, 539481u);
  EXPECT_EQ(s.on, 367855u);
  EXPECT_EQ(s.events - s.on, 171626u);
  EXPECT_EQ(s.first, ev(1317888, 237, 121, 1));
  EXPECT_EQ(s.last, ev(1367888, 210, 142, 1));
  EXPECT_EQ(s.last.t_ns - s.first.t_ns, 50'000'000);  // exactly 50 ms
  EXPECT_TRUE(s.sorted);
  EXPECT_EQ(s.min_x, 60);
  EXPECT_EQ(s.max_x, 599);
  EXPECT_EQ(s.min_y, 18);
  EXPECT_EQ(s.max_y, 475);
  EXPECT_EQ(readAllEvents(path, withPacketSize(777)).size(), 539481u);
}

TEST(PropheseeSamples, DatRecordingMatchesItsSourceFigures) {
  const std::string path = sample("dat/sample_ncars.dat");
  SKIP_WITHOUT(path);
  auto reader = openEventReader(path);
  EXPECT_EQ(reader->info().format, "dat");
  // The header has no Width/Height: the size is the events' bounding box (x 0..77, y 0..41).
  EXPECT_EQ(reader->info().width, 78);
  EXPECT_EQ(reader->info().height, 42);
  const Summary s = summarize(*reader);
  EXPECT_EQ(s.events, 2009u);
  EXPECT_EQ(s.on, 1350u);
  EXPECT_EQ(s.first, ev(0, 25, 8, -1));
  EXPECT_EQ(s.last, ev(99952, 75, 28, 1));
  EXPECT_TRUE(s.sorted);
  EXPECT_EQ(s.max_x, 77);
  EXPECT_EQ(s.max_y, 41);

  ReaderOptions options;  // a configured size replaces the bounding box (N-CARS crops a 304x240 ATIS)
  options.width = 304;
  options.height = 240;
  reader = openEventReader(path, options);
  EXPECT_EQ(reader->info().width, 304);
  EXPECT_EQ(summarize(*reader).events, 2009u);
}

TEST(PropheseeSamples, ExplicitFormatsAgreeWithAuto) {
  struct Case {
    const char* file;
    const char* format;
  };
  for (const Case& c : {Case{"evt3/evt3_sample.raw", "evt3"}, Case{"evt2/evt2_sample.raw", "evt2"},
                        Case{"dat/sample_ncars.dat", "dat"}}) {
    const std::string path = sample(c.file);
    SKIP_WITHOUT(path);
    ReaderOptions options;
    options.format = c.format;
    EXPECT_EQ(openEventReader(path, options)->info().format, c.format);
    EXPECT_EQ(readAllEvents(path, options), readAllEvents(path));
  }
}

TEST(PropheseeSamples, WrongExplicitFormatIsRejected) {
  const std::string path = sample("evt3/evt3_sample.raw");
  SKIP_WITHOUT(path);
  ReaderOptions options;
  options.format = "evt2";
  expectErrorAt(path, 0, "the header names the format EVT 3.0, not EVT 2.0 (read it with --format evt3 or auto)",
                options);
}

// ---------------------------------------------------------------------------------------------------
// EVT 3.0 fixtures

TEST(Evt3Reader, DecodesEveryWordKindIncludingVectors) {
  TempDir dir;
  const auto path = dir.write("all_words.raw",
                              kEvt3Header + evt3Words({
                                                addrX(5, 1),         // before any time base: skipped
                                                timeHigh(1),         //
                                                timeLow(5),          // t = 1 << 12 | 5 = 4101 us
                                                addrY(3),            //
                                                addrX(7, 1),         // (7, 3) ON
                                                vectBaseX(10, 0),    //
                                                vect12(0x805),       // bits 0, 2, 11: x = 10, 12, 21, OFF
                                                vect8(0x81),         // base now 22; bits 0, 7: x = 22, 29
                                                0xA001,              // EXT_TRIGGER, channel 0, rising
                                                0xE123,              // OTHERS
                                                0x7005,              // CONTINUED_4
                                                0xF456,              // CONTINUED_12
                                                timeLow(9),          // t = 4105 us
                                                addrY(31) | 0x800,   // y = 31; bit 11 (system type) ignored
                                                vectBaseX(60, 1),    //
                                                vect8(0x09),         // x = 60, 63, ON
                                                addrX(0, 0),         // (0, 31) OFF
                                            }));
  const std::vector<Event> expected = {ev(4101, 7, 3, 1),   ev(4101, 10, 3, -1), ev(4101, 12, 3, -1),
                                       ev(4101, 21, 3, -1), ev(4101, 22, 3, -1), ev(4101, 29, 3, -1),
                                       ev(4105, 60, 31, 1), ev(4105, 63, 31, 1), ev(4105, 0, 31, -1)};
  for (const int packet_size : {1, 2, 4, 100}) {
    auto reader = openEventReader(path, withPacketSize(packet_size));
    EXPECT_EQ(reader->info().format, "evt3");
    EXPECT_EQ(reader->info().width, 64);
    EXPECT_EQ(reader->info().height, 32);
    std::vector<Event> got;
    EventPacket packet;
    while (reader->read(packet)) {
      EXPECT_LE(packet.size(), static_cast<std::size_t>(packet_size));
      EXPECT_EQ(packet.first_index, got.size());
      got.insert(got.end(), packet.events.begin(), packet.events.end());
    }
    EXPECT_EQ(got, expected) << "packet size " << packet_size;
    EXPECT_EQ(reader->stats().events, expected.size());
    EXPECT_EQ(reader->stats().trigger_events, 1u);
    EXPECT_EQ(reader->stats().ignored_words, 4u);  // the early ADDR_X, OTHERS, CONTINUED_4, CONTINUED_12
  }
}

TEST(Evt3Reader, TimeBaseWrapsAroundTo64Bits) {
  TempDir dir;
  const auto path = dir.write("wrap.raw", kEvt3Header + evt3Words({
                                                            timeHigh(4095), timeLow(4000), addrY(0), addrX(1, 1),
                                                            timeHigh(0), timeLow(10), addrX(2, 1),    // wrapped
                                                            timeHigh(1), timeLow(0), addrX(3, 1),     //
                                                            timeHigh(4095), timeLow(1), addrX(4, 1),  // again
                                                            timeHigh(0), timeLow(2), addrX(5, 1),     // wrap 2
                                                        }));
  const int64_t wrap = int64_t{1} << 24;
  EXPECT_EQ(readAllEvents(path), (std::vector<Event>{ev(4095 * 4096 + 4000, 1, 0, 1), ev(wrap + 10, 2, 0, 1),
                                                     ev(wrap + 4096, 3, 0, 1), ev(wrap + 4095 * 4096 + 1, 4, 0, 1),
                                                     ev(2 * wrap + 2, 5, 0, 1)}));
}

TEST(Evt3Reader, TimeLowGoingBackIsNotAWrap) {
  TempDir dir;
  const std::string words = evt3Words({timeHigh(2), timeLow(4000), addrY(0), addrX(1, 0), timeLow(10), addrX(2, 0)});
  const auto path = dir.write("back.raw", kEvt3Header + words);
  // The second ADDR_X (word 5) is 3990 us earlier than the first: an error, not 4096 us later.
  expectErrorAt(path, kEvt3Header.size() + 10, "time goes backwards by 3990000 ns");
  ReaderOptions tolerant;  // within the tolerance the time is clamped and counted
  tolerant.max_time_reversal_ns = 4'000'000;
  auto reader = openEventReader(path, tolerant);
  EventPacket packet;
  ASSERT_TRUE(reader->read(packet));
  ASSERT_EQ(packet.size(), 2u);
  EXPECT_EQ(packet.events[1].t_ns, packet.events[0].t_ns);
  EXPECT_EQ(reader->stats().clamped_times, 1u);
}

TEST(Evt3Reader, TimeHighGoingBackALittleIsAnError) {
  TempDir dir;
  const auto path = dir.write("back_high.raw", kEvt3Header + evt3Words({timeHigh(100), addrY(0), addrX(1, 0),
                                                                        timeHigh(99), addrX(2, 0)}));
  expectErrorAt(path, kEvt3Header.size() + 8, "time goes backwards by 4096000 ns");
}

TEST(Evt3Reader, HeaderEndsAtEndKeywordOrAtBinaryBytes) {
  TempDir dir;
  // The first data word 0x2025 is the bytes "% ": after "% end" it is data.
  auto path = dir.write("end.raw", kEvt3Header + evt3Words({addrX(37, 0), timeHigh(1), addrY(2), addrX(37, 0)}));
  auto reader = openEventReader(path);
  EXPECT_EQ(readAllEvents(path), (std::vector<Event>{ev(4096, 37, 2, -1)}));
  // Without "% end", "% " followed by a control byte (0x80 0x01 = TIME_HIGH 1 reads "\x01\x80") ends the
  // header too.
  path = dir.write("no_end.raw", "% evt 3.0\n% geometry 64x32\n" + evt3Words({addrX(37, 0), timeHigh(1), addrY(2),
                                                                              addrX(37, 0)}));
  reader = openEventReader(path);
  EXPECT_EQ(reader->info().width, 64);
  EventPacket packet;
  ASSERT_TRUE(reader->read(packet));
  EXPECT_EQ(packet.events, (std::vector<Event>{ev(4096, 37, 2, -1)}));
  EXPECT_EQ(reader->stats().ignored_words, 1u);
}

// ---------------------------------------------------------------------------------------------------
// EVT 2.0 fixtures

TEST(Evt2Reader, DecodesCdEventsTriggersAndTimeWrap) {
  TempDir dir;
  const auto path = dir.write("all_words.raw", kEvt2Header + evt2Words({
                                                                 cd(1, 0, 1, 1),        // no time base yet: skipped
                                                                 timeHigh2(5),          // t = 5 << 6 = 320 us
                                                                 cd(1, 3, 100, 50),     // 323 us, ON
                                                                 0xA0000101,            // EXT_TRIGGER
                                                                 0xE0000000,            // OTHERS
                                                                 0xF0000000,            // CONTINUED
                                                                 cd(0, 63, 639, 479),   // 383 us, OFF
                                                                 timeHigh2(0x0FFFFFFF), //
                                                                 cd(1, 1, 2, 2),        //
                                                                 timeHigh2(0),          // the 34-bit time wraps
                                                                 cd(0, 2, 3, 3),        //
                                                             }));
  const int64_t top = int64_t{0x0FFFFFFF} << 6;
  const int64_t wrap = int64_t{1} << 34;
  const std::vector<Event> expected = {ev(323, 100, 50, 1), ev(383, 639, 479, -1), ev(top + 1, 2, 2, 1),
                                       ev(wrap + 2, 3, 3, -1)};
  for (const int packet_size : {1, 3, 100}) {
    auto reader = openEventReader(path, withPacketSize(packet_size));
    EXPECT_EQ(reader->info().format, "evt2");
    EXPECT_EQ(reader->info().width, 640);
    EXPECT_EQ(reader->info().height, 480);
    std::vector<Event> got;
    EventPacket packet;
    while (reader->read(packet)) got.insert(got.end(), packet.events.begin(), packet.events.end());
    EXPECT_EQ(got, expected);
    EXPECT_EQ(reader->stats().trigger_events, 1u);
    EXPECT_EQ(reader->stats().ignored_words, 3u);
  }
}

// ---------------------------------------------------------------------------------------------------
// DAT fixtures

TEST(DatReader, DecodesRecordsWithHeaderGeometryAndTimeWrap) {
  TempDir dir;
  const auto path = dir.write("cd.dat", kDatHeader + kDatCdTypeSize + datRecord(10, 5, 6, 1) +
                                            datRecord(20, 639, 479, 0) + datRecord(0xFFFFFFF0u, 1, 1, 1) +
                                            datRecord(5, 2, 2, 0));
  auto reader = openEventReader(path, withPacketSize(3));
  EXPECT_EQ(reader->info().format, "dat");
  EXPECT_EQ(reader->info().width, 640);
  EXPECT_EQ(reader->info().height, 480);
  EXPECT_EQ(readAllEvents(path), (std::vector<Event>{ev(10, 5, 6, 1), ev(20, 639, 479, -1),
                                                     ev(0xFFFFFFF0ll, 1, 1, 1), ev((1ll << 32) + 5, 2, 2, -1)}));
  // Event2d (type 0x00, the older name of the same record) reads the same way.
  const auto event2d = dir.write("e2d.dat", "% Data file containing Event2d events\n% Version 2\n" +
                                                std::string("\x00\x08", 2) + datRecord(7, 3, 4, 1));
  EXPECT_EQ(readAllEvents(event2d), (std::vector<Event>{ev(7, 3, 4, 1)}));
}

// ---------------------------------------------------------------------------------------------------
// Geometry and detection

TEST(PropheseeGeometry, TakenFromTheHeaderInEverySpelling) {
  TempDir dir;
  const std::string data = evt3Words({timeHigh(1), addrY(4), addrX(9, 1)});
  struct Case {
    const char* header;
    int width;
    int height;
  };
  const Case cases[] = {
      {"% evt 3.0\n% geometry 320x240\n", 320, 240},
      {"% evt 3.0\n% format EVT3;height=240;width=320\n", 320, 240},
      {"% format EVT3;height=240;width=320\n% end\n", 320, 240},  // no 'evt' line
      {"% evt 3.0\n% width 320\n% height 240\n", 320, 240},
      {"% evt 3.0\n% plugin_name hal_plugin_imx636_evk4\n", 1280, 720},  // known camera
      {"% evt 3.0\n% plugin_name hal_plugin_gen41_evk3\n", 1280, 720},
      {"% evt 3.0\n% plugin_name someone_elses_camera\n", 10, 5},         // bounding box of the events
      {"% evt 3.0\n", 10, 5},
  };
  for (const Case& c : cases) {
    const auto path = dir.write("g.raw", c.header + data);
    auto reader = openEventReader(path);
    EXPECT_EQ(reader->info().format, "evt3") << c.header;
    EXPECT_EQ(reader->info().width, c.width) << c.header;
    EXPECT_EQ(reader->info().height, c.height) << c.header;
    EXPECT_EQ(readAllEvents(path), (std::vector<Event>{ev(4096, 9, 4, 1)})) << c.header;
  }
}

TEST(PropheseeGeometry, ConfiguredSizeMustAgreeWithTheHeader) {
  TempDir dir;
  const std::string header = "% evt 3.0\n% geometry 320x240\n";
  const auto path = dir.write("g.raw", header + evt3Words({timeHigh(1), addrY(4), addrX(9, 1)}));
  ReaderOptions options;
  options.width = 320;
  options.height = 240;
  EXPECT_EQ(readAllEvents(path, options).size(), 1u);
  options.width = 640;
  options.height = 480;
  options.size_origin = "--sensor";
  expectErrorAt(path, 10, "sensor size 320x240 in the header differs from 640x480 set by --sensor", options);
  // A known camera's size is only a default: a configured size replaces it.
  const auto known = dir.write("k.raw", "% evt 3.0\n% plugin_name hal_plugin_imx636_evk4\n" +
                                            evt3Words({timeHigh(1), addrY(4), addrX(9, 1)}));
  EXPECT_EQ(openEventReader(known, options)->info().width, 640);
}

TEST(PropheseeDetection, AutoPicksEachFormatByContent) {
  TempDir dir;
  const auto evt3 = dir.write("a.bin", kEvt3Header + evt3Words({timeHigh(1), addrY(1), addrX(1, 1)}));
  const auto evt2 = dir.write("b.bin", kEvt2Header + evt2Words({timeHigh2(1), cd(1, 0, 1, 1)}));
  const auto dat = dir.write("c.bin", kDatHeader + kDatCdTypeSize + datRecord(1, 1, 1, 1));
  const auto legacy = dir.write("d.bin", "% plugin_name hal_plugin_gen3_fx3\n% serial_number 1\n" +
                                             evt2Words({timeHigh2(1), cd(1, 0, 1, 1)}));
  EXPECT_EQ(openEventReader(evt3)->info().format, "evt3");
  EXPECT_EQ(openEventReader(evt2)->info().format, "evt2");
  EXPECT_EQ(openEventReader(dat)->info().format, "dat");
  EXPECT_EQ(openEventReader(legacy)->info().format, "evt2");  // Gen3's default encoding
  for (const auto& path : {evt3, evt2, dat, legacy}) EXPECT_EQ(readAllEvents(path).size(), 1u) << path;
}

TEST(PropheseeDetection, HeadersNamingNoOrUnsupportedFormatsAreRejected) {
  TempDir dir;
  auto path = dir.write("x.raw", "% date 2024-01-01\n% serial_number 1\n" + evt3Words({timeHigh(1)}));
  EXPECT_NE(errorOf(path).find(path + ": a '%' header that names no Prophesee format"), std::string::npos)
      << errorOf(path);
  path = dir.write("x.raw", "% date 2024-01-01\n% evt 2.1\n" + evt3Words({timeHigh(1)}));
  expectErrorAt(path, 18, "the header names the encoding 'evt 2.1', which AsynEVO does not decode");
  path = dir.write("x.raw", "% format EVT21;height=720;width=1280\n" + evt3Words({timeHigh(1)}));
  expectErrorAt(path, 0, "the header names the format 'EVT21', which AsynEVO does not decode");
  path = dir.write("x.raw", "% evt 3.0\n% format EVT2;height=720;width=1280\n" + evt3Words({timeHigh(1)}));
  expectErrorAt(path, 10, "the header's 'evt 3.0' and 'format EVT2;height=720;width=1280' lines disagree");
  path = dir.write("x.raw", "% evt 3.0\n% geometry 64by32\n" + evt3Words({timeHigh(1)}));
  expectErrorAt(path, 10, "header line 'geometry 64by32' is not 'geometry WxH'");
  path = dir.write("x.raw", "% evt 3.0\n% geometry 4096x32\n" + evt3Words({timeHigh(1)}));
  expectErrorAt(path, 10, "sensor size 4096x32 in the header is outside 1..2048");
}

// ---------------------------------------------------------------------------------------------------
// Bad input: every message names the file and the byte offset.

TEST(PropheseeBadInput, TruncatedFiles) {
  TempDir dir;
  auto path = dir.write("t3.raw", kEvt3Header + evt3Words({timeHigh(1), addrY(0), addrX(1, 1)}) + "\x01");
  expectErrorAt(path, kEvt3Header.size() + 6, "truncated: the last EVT 3.0 word has only 1 of its 2 bytes");
  path = dir.write("t2.raw", kEvt2Header + evt2Words({timeHigh2(1), cd(1, 0, 1, 1)}) + "abc");
  expectErrorAt(path, kEvt2Header.size() + 8, "truncated: the last EVT 2.0 word has only 3 of its 4 bytes");
  path = dir.write("t.dat", kDatHeader + kDatCdTypeSize + datRecord(1, 1, 1, 1) + datRecord(2, 2, 2, 1).substr(0, 5));
  expectErrorAt(path, kDatHeader.size() + 2 + 8, "truncated: the last DAT event record has only 5 of its 8 bytes");
  path = dir.write("h.dat", "% Data file containing CD events\n% Version 2");
  expectErrorAt(path, 33, "truncated: the file ends inside its '%' header");
  path = dir.write("n.dat", "% Data file containing CD events\n% Version 2\n");
  expectErrorAt(path, 45, "truncated: no event type and size bytes after the DAT header");
}

TEST(PropheseeBadInput, WrongMagicOrType) {
  TempDir dir;
  ReaderOptions dat;
  dat.format = "dat";
  auto path = dir.write("aevt.bin", std::string("ASYNEVOE\x01\x00\x00\x00", 12));
  expectErrorAt(path, 0, "unknown DAT event type 0x41", dat);
  path = dir.write("size.dat", kDatHeader + std::string("\x0C\x10", 2) + datRecord(1, 1, 1, 1));
  expectErrorAt(path, kDatHeader.size() + 1, "DAT event size 16 bytes, expected 8");
  path = dir.write("trig.dat", kDatHeader + std::string("\x0E\x08", 2) + datRecord(1, 1, 1, 1));
  expectErrorAt(path, kDatHeader.size(), "this DAT file holds external-trigger events (type 0x0E), not CD events");
  ReaderOptions evt3;
  evt3.format = "evt3";
  path = dir.write("cd.dat", kDatHeader + kDatCdTypeSize + datRecord(1, 1, 1, 1));
  expectErrorAt(path, 0, "the header names the format DAT, not EVT 3.0 (read it with --format dat or auto)", evt3);
}

TEST(PropheseeBadInput, UnknownWordTypes) {
  TempDir dir;
  auto path = dir.write("u3.raw", kEvt3Header + evt3Words({timeHigh(1), 0x1234}));
  expectErrorAt(path, kEvt3Header.size() + 2, "unknown EVT 3.0 word type 0001 (word 0x1234)");
  for (const uint32_t type : {0x9u, 0xBu, 0xCu, 0xDu}) {
    path = dir.write("u3.raw", kEvt3Header + evt3Words({timeHigh(1), type << 12}));
    EXPECT_NE(errorOf(path).find(": byte " + std::to_string(kEvt3Header.size() + 2) + ": unknown EVT 3.0 word type"),
              std::string::npos)
        << errorOf(path);
  }
  path = dir.write("u2.raw", kEvt2Header + evt2Words({timeHigh2(1), cd(1, 0, 1, 1), 0x30000000}));
  expectErrorAt(path, kEvt2Header.size() + 8, "unknown EVT 2.0 word type 0011 (word 0x30000000)");
}

TEST(PropheseeBadInput, TimeGoingBackwards) {
  TempDir dir;
  auto path = dir.write("b2.raw", kEvt2Header + evt2Words({timeHigh2(10), cd(1, 0, 1, 1), timeHigh2(9), cd(1, 0, 1, 1)}));
  expectErrorAt(path, kEvt2Header.size() + 12, "time goes backwards by 64000 ns");
  path = dir.write("b.dat", kDatHeader + kDatCdTypeSize + datRecord(100, 1, 1, 1) + datRecord(50, 1, 1, 1));
  expectErrorAt(path, kDatHeader.size() + 2 + 8, "time goes backwards by 50000 ns");
}

TEST(PropheseeBadInput, EventsOutsideTheHeaderGeometry) {
  TempDir dir;
  auto path = dir.write("x3.raw", kEvt3Header + evt3Words({timeHigh(1), addrY(3), addrX(63, 1), addrX(64, 1)}));
  expectErrorAt(path, kEvt3Header.size() + 6, "pixel (64, 3) is outside the 64x32 sensor");
  path = dir.write("v3.raw", kEvt3Header + evt3Words({timeHigh(1), addrY(3), vectBaseX(60, 1), vect8(0x10)}));
  expectErrorAt(path, kEvt3Header.size() + 6, "pixel (64, 3) is outside the 64x32 sensor");  // the vector word
  path = dir.write("y3.raw", kEvt3Header + evt3Words({timeHigh(1), addrY(32), addrX(0, 1)}));
  expectErrorAt(path, kEvt3Header.size() + 4, "pixel (0, 32) is outside the 64x32 sensor");
  path = dir.write("x2.raw", kEvt2Header + evt2Words({timeHigh2(1), cd(1, 0, 639, 480)}));
  expectErrorAt(path, kEvt2Header.size() + 4, "pixel (639, 480) is outside the 640x480 sensor");
  path = dir.write("x.dat", kDatHeader + kDatCdTypeSize + datRecord(1, 640, 0, 1));
  expectErrorAt(path, kDatHeader.size() + 2, "pixel (640, 0) is outside the 640x480 sensor");
  path = dir.write("p.dat", kDatHeader + kDatCdTypeSize + datRecord(1, 1, 1, 7));
  expectErrorAt(path, kDatHeader.size() + 2, "polarity 7 is not one of 0, 1, -1");
}

// Time words that wrap the counter again and again push the time past int64 nanoseconds: a located
// error at the word or record where it leaves the range, not a signed overflow (found 2026-11-26 while
// fuzzing: UBSan "signed integer overflow" in the EVT 2.0 decoder; before, the wrapped-around time
// surfaced as a misleading "time goes backwards"). EVT 3.0 has the same check but needs ~2 GB of words.
TEST(PropheseeBadInput, TimeWrappedPastTheInt64RangeIsAnError) {
  TempDir dir;
  // EVT 2.0: TIME_HIGH 0x0FFFFFFF then 0 is one wrap of the 34-bit µs counter (2^34 µs); after 536870
  // wraps the next TIME_HIGH 0x0FFFFFFF (word 1073740) is above INT64_MAX / 1000 µs.
  std::string words;
  const std::string pair = le32(timeHigh2(0x0FFFFFFF)) + le32(timeHigh2(0));
  for (int i = 0; i < 536871; ++i) words += pair;
  auto path = dir.write("wraps.raw", kEvt2Header + words + evt2Words({cd(1, 0, 1, 1)}));
  expectErrorAt(path, kEvt2Header.size() + 4 * uint64_t{1073740},
                "time 9223373548683200 µs after 536870 wraps of the EVT 2.0 time counter is out of range");
  // DAT: records at 0xFFFFFFFF then 0 µs are one wrap of the 32-bit counter; record 4294966 is the first
  // past the range.
  std::string records;
  const std::string two = datRecord(0xFFFFFFFFu, 1, 1, 1) + datRecord(0, 1, 1, 1);
  records.reserve(two.size() * 2147484);
  for (int i = 0; i < 2147484; ++i) records += two;
  path = dir.write("wraps.dat", kDatHeader + kDatCdTypeSize + records);
  records = std::string();
  std::string message;
  try {  // packet by packet: readAllEvents would hold the 4 million events before the error
    auto reader = openEventReader(path);
    EventPacket packet;
    while (reader->read(packet)) {
    }
  } catch (const InputError& e) {
    message = e.what();
  }
  const std::string expected = path + ": byte " + std::to_string(kDatHeader.size() + 2 + 8 * uint64_t{4294966}) +
                               ": time 9223373548683263 µs after 2147483 wraps of the DAT time counter is out of range";
  EXPECT_EQ(message.substr(0, expected.size()), expected) << "full message: " << message;
}

// Corrupt data never crashes a reader: every random byte string after a valid header either decodes or
// stops with an InputError that names the file and a byte offset inside it.
TEST(PropheseeBadInput, RandomBytesDecodeOrFailCleanly) {
  TempDir dir;
  std::minstd_rand rng(22);
  const std::pair<std::string, std::string> headers[] = {
      {kEvt3Header, "evt3"}, {kEvt2Header, "evt2"}, {kDatHeader + kDatCdTypeSize, "dat"}, {"% evt 3.0\n", "evt3"}};
  int failures = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const auto& [header, format] = headers[trial % 4];
    std::string bytes = header;
    const std::size_t size = rng() % 300;
    for (std::size_t i = 0; i < size; ++i) bytes += static_cast<char>(rng() & 0xFF);
    const auto path = dir.write("fuzz.bin", bytes);
    for (const int packet_size : {1, 7, 65536}) {
      ReaderOptions options = withPacketSize(packet_size);
      options.format = trial % 8 < 4 ? "auto" : format;
      try {
        auto reader = openEventReader(path, options);
        EventPacket packet;
        while (reader->read(packet)) {
          for (const Event& e : packet.events) {
            ASSERT_LT(e.x, reader->info().width);
            ASSERT_LT(e.y, reader->info().height);
          }
        }
      } catch (const InputError& e) {
        ++failures;
        const std::string message = e.what();
        ASSERT_EQ(message.rfind(path + ": byte ", 0), 0u) << message;
        EXPECT_LE(e.location(), bytes.size()) << message;
      }
    }
  }
  EXPECT_GT(failures, 0);  // the random data does hit the error paths
}

}  // namespace
}  // namespace asynevo
