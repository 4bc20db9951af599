// 'asynevo info' on Prophesee RAW (EVT 3.0, EVT 2.0) and DAT files: the real sample recordings of
// ../shared/data/formats (skipped when that folder is missing; figures from ../shared/data/SOURCES.md)
// and byte-built bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::runAsynevo;
using testing::TempDir;

TEST(InfoCommand, DescribesPropheseeRecordings) {
  struct Expected {
    const char* file;
    const char* format_line;
    const char* sensor_line;
    const char* events_line;
    const char* span_line;
  };
  const Expected samples[] = {
      {"evt3/evt3_sample.raw", "format        evt3\n", "sensor        1280 x 720 (from the camera the header names)\n", "events        219596\n",
       "time span     11.718656000 .. 11.727457000 s"},
      {"evt2/evt2_sample.raw", "format        evt2\n", "sensor        640 x 480 (from the camera the header names)\n", "events        539481\n",
       "time span     1.317888000 .. 1.367888000 s (0.050000 s)"},
      {"dat/sample_ncars.dat", "format        dat\n", "sensor        78 x 42 (from the events' extent, the header states no size)\n", "events        2009\n",
       "time span     0.000000000 .. 0.099952000 s"},
  };
  for (const Expected& s : samples) {
    const std::string path = testing::sharedFormatSample(s.file);
    if (!std::filesystem::exists(path)) {
      GTEST_SKIP() << "sample recording " << path << " not found: the shared data folder (../shared/data beside the "
                   << "repository) is missing; these GPL files are not copied into the repository";
    }
    const auto result = runAsynevo("info --dataset " + path);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    for (const char* line : {s.format_line, s.sensor_line, s.events_line, s.span_line}) {
      EXPECT_NE(result.output.find(line), std::string::npos) << "expected '" << line << "' in:\n" << result.output;
    }
  }
}

TEST(InfoCommand, ExplicitPropheseeFormatMustMatchTheHeader) {
  const std::string path = testing::sharedFormatSample("evt3/evt3_sample.raw");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "sample recording " << path << " not found (../shared/data missing)";
  const auto result = runAsynevo("info --format evt2 --dataset " + path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("asynevo: error: " + path + ": byte 0: the header names the format EVT 3.0, not EVT 2.0"),
            std::string::npos)
      << result.output;
}

// A byte-built EVT 3.0 file: TIME_HIGH 1, ADDR_Y 3, ADDR_X 5 ON, EXT_TRIGGER, OTHERS.
TEST(InfoCommand, CountsPropheseeTriggersAndSkippedWords) {
  TempDir dir;
  const auto path = dir.write("rec.raw", "% evt 3.0\n% geometry 64x32\n% end\n" +
                                             std::string("\x01\x80\x03\x00\x05\x28\x01\xA0\x00\xE0", 10));
  const auto result = runAsynevo("info --dataset " + path);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  for (const char* line : {"format        evt3\n", "sensor        64 x 32 (from the file's header)\n", "events        1\n",
                           "time span     0.004096000 .. 0.004096000 s", "triggers      1 external-trigger events",
                           "skipped       1 encoded words"}) {
    EXPECT_NE(result.output.find(line), std::string::npos) << "expected '" << line << "' in:\n" << result.output;
  }
}

// Bad input built from the specification's bit layouts: exit code 1 and a message with file and byte offset.
TEST(InfoCommand, BadPropheseeInputExitsWithOneAndNamesTheByte) {
  const std::string header = "% evt 3.0\n% geometry 64x32\n% end\n";  // 33 bytes
  struct Case {
    std::string content;
    const char* message;
  };
  const Case cases[] = {
      // TIME_HIGH 1, ADDR_Y 0, then one byte of a word
      {header + std::string("\x01\x80\x00\x00\x01", 5), "byte 37: truncated: the last EVT 3.0 word has only 1 of its 2 bytes"},
      // TIME_HIGH 1, then a word of the reserved type 1001
      {header + std::string("\x01\x80\x00\x90", 4), "byte 35: unknown EVT 3.0 word type 1001"},
      // TIME_HIGH 1, ADDR_Y 3, ADDR_X 64 (outside the 64-column sensor)
      {header + std::string("\x01\x80\x03\x00\x40\x20", 6), "byte 37: pixel (64, 3) is outside the 64x32 sensor"},
  };
  for (const Case& c : cases) {
    TempDir dir;
    testing::expectInfoFails(dir.file("rec.raw"), c.content, c.message);
  }
}

}  // namespace
}  // namespace asynevo
