#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "asynevo/io/event_reader.hpp"
#include "cli_test_util.hpp"
#include "dsec_fixture.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::runAsynevo;
using testing::TempDir;

TEST(ConvertCommand, ProducesAnEquivalentBinaryFileThatInfoReads) {
  TempDir dir;
  const auto out = dir.file("events.aevt");
  const auto result = runAsynevo("convert --dataset " + dataPath("ecd/boxes_rotation") + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("wrote 30000 events (240x180)"), std::string::npos) << result.output;
  EXPECT_EQ(readAllEvents(out), readAllEvents(dataPath("ecd/boxes_rotation/events.txt")));
  const auto info = runAsynevo("info --dataset " + out);
  EXPECT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("format        aevt"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("time span     13.582595999 .. 13.595874999 s"), std::string::npos) << info.output;
}

TEST(ConvertCommand, BadInputLeavesNoOutputFile) {
  TempDir dir;
  dir.write("events.txt", "0.1 1 2 1\n0.2 1 2\n");
  const auto out = dir.file("events.aevt");
  const auto result = runAsynevo("convert --dataset " + dir.file("events.txt") + " --out " + out);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("events.txt:2: expected 4 fields"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// aevt -> ECD text -> aevt gives the same bytes: ECD text with 9 decimals holds every int64 ns time exactly.
TEST(ConvertCommand, AevtToEcdTextAndBackIsIdentical) {
  TempDir dir;
  const auto a = dir.file("a.aevt");
  const auto text = dir.file("events.txt");
  const auto b = dir.file("b.aevt");
  ASSERT_EQ(runAsynevo("convert --dataset " + dataPath("ecd/boxes_rotation") + " --out " + a).exit_code, 0);
  const auto to_text = runAsynevo("convert --dataset " + a + " --out " + text);
  ASSERT_EQ(to_text.exit_code, 0) << to_text.output;
  EXPECT_NE(to_text.output.find("as ECD text"), std::string::npos) << to_text.output;
  const auto back = runAsynevo("convert --dataset " + text + " --out " + b);
  ASSERT_EQ(back.exit_code, 0) << back.output;
  EXPECT_EQ(bytesOf(a), bytesOf(b));
  EXPECT_EQ(readAllEvents(text), readAllEvents(a));
  // --out-format overrides the extension; an unknown extension without it is a usage error.
  const auto named = dir.file("events.ecd");
  ASSERT_EQ(runAsynevo("convert --dataset " + a + " --out " + named + " --out-format ecd").exit_code, 0);
  EXPECT_EQ(bytesOf(named), bytesOf(text));
  const auto unknown = runAsynevo("convert --dataset " + a + " --out " + dir.file("x.bin"));
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.output.find("cannot tell the output format from the file name"), std::string::npos)
      << unknown.output;
  EXPECT_EQ(runAsynevo("convert --dataset " + a + " --out " + named + " --out-format csv").exit_code, 105);
}

// DSEC-style HDF5 -> aevt -> ECD text: the same events at every step (the size comes from --sensor).
TEST(ConvertCommand, DsecHdf5ToAevtAndEcdTextKeepsEveryEvent) {
  TempDir dir;
  const auto h5 = dir.file("events.h5");
  const testing::DsecEvents events = testing::syntheticDsecEvents(5000);
  testing::DsecLayout layout;
  layout.t_offset_us = 49'599'300'523;
  testing::writeDsecEvents(h5, events, layout);
  const auto aevt = dir.file("events.aevt");
  const auto text = dir.file("events.txt");
  const auto to_aevt = runAsynevo("convert --dataset " + h5 + " --sensor 640x480 --out " + aevt);
  ASSERT_EQ(to_aevt.exit_code, 0) << to_aevt.output;
  EXPECT_NE(to_aevt.output.find("wrote 5000 events (640x480)"), std::string::npos) << to_aevt.output;
  ReaderOptions vga;
  vga.width = 640;
  vga.height = 480;
  const std::vector<Event> original = readAllEvents(h5, vga);
  EXPECT_EQ(readAllEvents(aevt), original);
  ASSERT_EQ(runAsynevo("convert --dataset " + aevt + " --out " + text).exit_code, 0);
  EXPECT_EQ(readAllEvents(text, vga), original);
  const auto info = runAsynevo("info --dataset " + h5 + " --sensor 640x480");
  EXPECT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("format        dsec"), std::string::npos) << info.output;
  const auto no_size = runAsynevo("info --dataset " + h5);
  EXPECT_NE(no_size.exit_code, 0);
  EXPECT_NE(no_size.output.find("DSEC-style HDF5 files store no sensor size"), std::string::npos) << no_size.output;
}

// The real sample recordings of ../shared/data/formats (several GPL, read from there, not copied; counts
// from ../shared/data/SOURCES.md) -> aevt -> ECD text: the same events at every step, for every format
// that has a sample (the "same events through every format").
TEST(ConvertCommand, EveryRealSampleKeepsItsEventsThroughAevtAndEcdText) {
  struct Sample {
    const char* file;
    std::size_t events;
  };
  const Sample samples[] = {
      {"evt3/evt3_sample.raw", 219596},         {"evt2/evt2_sample.raw", 539481},
      {"dat/sample_ncars.dat", 2009},           {"aedat4/sample.aedat4", 111954},
      {"aedat4/sample_davis346_trimmed.aedat4", 6676}, {"rosbag/test_events_1.bag", 343474},
  };
  for (const Sample& sample : samples) {
    SCOPED_TRACE(sample.file);
    const std::string path = testing::sharedFormatSample(sample.file);
    if (!std::filesystem::exists(path)) {
      GTEST_SKIP() << "sample recording " << path << " not found: the shared data folder (../shared/data beside "
                   << "the repository) is missing; these GPL files are not copied into the repository";
    }
    TempDir dir;
    const auto aevt = dir.file("events.aevt");
    const auto text = dir.file("events.txt");
    const auto to_aevt = runAsynevo("convert --dataset " + path + " --out " + aevt);
    ASSERT_EQ(to_aevt.exit_code, 0) << to_aevt.output;
    const std::vector<Event> original = readAllEvents(path);
    ASSERT_EQ(original.size(), sample.events);
    EXPECT_EQ(readAllEvents(aevt), original);
    const auto to_text = runAsynevo("convert --dataset " + aevt + " --out " + text);
    ASSERT_EQ(to_text.exit_code, 0) << to_text.output;
    // ECD text stores no sensor size: the aevt header's is given back.
    const StreamInfo size = openEventReader(aevt)->info();
    ReaderOptions options;
    options.width = size.width;
    options.height = size.height;
    EXPECT_EQ(readAllEvents(text, options), original);
  }
}

}  // namespace
}  // namespace asynevo
