// 'asynevo info' on AEDAT 4.0 files: the DVXplorer sample of ../shared/data/formats/aedat4 (skipped when
// that folder is missing; figures from ../shared/data/SOURCES.md) and byte-built bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "aedat4_fixture.hpp"
#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::runAsynevo;
using testing::TempDir;
namespace fx = testing::aedat4;

TEST(InfoCommand, DescribesAnAedat4RecordingAndItsStreams) {
  const std::string path = testing::sharedFormatSample("aedat4/sample.aedat4");
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "sample recording " << path << " not found: the shared data folder (../shared/data beside the "
                 << "repository) is missing; this GPL file is not copied into the repository";
  }
  const auto result = runAsynevo("info --dataset " + path);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  for (const char* line : {"format        aedat4\n", "sensor        320 x 240 (from the file's stream description)\n", "events        111954\n",
                           "time span     1605537493.718345000 .. 1605537494.308262000 s",
                           "imu           475 samples (counted, not used)\n",
                           "streams       id 0 EVTS 'events' 320x240: 59 packets, 111954 events (read)\n",
                           "              id 2 IMUS 'imu': 59 packets, 475 samples (counted)\n",
                           "              id 3 TRIG 'triggers': 0 packets, 0 triggers (counted)\n"}) {
    EXPECT_NE(result.output.find(line), std::string::npos) << "expected '" << line << "' in:\n" << result.output;
  }
}

TEST(InfoCommand, BadAedat4InputExitsWithOneAndNamesTheByte) {
  const std::string xml = fx::infoXml({{0, "EVTS", "events", 8, 8}});
  const std::string header = fx::kMagic + fx::ioHeader(fx::kLz4, -1, xml);
  const std::string start = std::to_string(header.size());
  const std::string frame = fx::compress(fx::eventPacket({{5, 1, 1, 1}}), fx::kLz4);
  struct Case {
    std::string content;
    std::string message;
  };
  const Case cases[] = {
      {fx::kMagic + fx::ioHeader(9, -1, xml), "byte 18: unknown compression type 9 in the IOHeader"},
      {header + fx::packet(0, frame).substr(0, 20), "byte " + start + ": truncated: packet 0 (stream 0, EVTS) declares"},
      {header + fx::packet(0, frame.substr(0, 8) + "corrupt" + frame.substr(15)),
       "byte " + start + ": packet 0 (stream 0, EVTS): LZ4 frame: "},
      {header + fx::packet(0, fx::compress(fx::eventPacket({{5, 8, 1, 1}}), fx::kLz4)),
       "byte " + start + ": packet 0 (stream 0, EVTS), event 0: pixel (8, 1) is outside the 8x8 sensor"},
  };
  for (const Case& c : cases) {
    TempDir dir;
    testing::expectInfoFails(dir.file("rec.aedat4"), c.content, c.message);
  }
}

}  // namespace
}  // namespace asynevo
