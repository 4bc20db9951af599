#include <gtest/gtest.h>

#include <filesystem>

#include "asynevo/io/event_reader.hpp"
#include "cli_test_util.hpp"
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

}  // namespace
}  // namespace asynevo
