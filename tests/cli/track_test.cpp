// 'asynevo track': the frontend alone, as a user runs it.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::runAsynevo;
using testing::TempDir;

struct Line {
  int64_t id;
  double t;
  double x, y;
};

/// Parses tracks.txt strictly: four fields per line, an integer id, finite numbers.
std::vector<Line> readTracks(const std::string& path) {
  std::vector<Line> lines;
  std::ifstream in(path);
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    std::istringstream fields(text);
    std::string id_text, extra;
    Line l{};
    fields >> id_text >> l.t >> l.x >> l.y;
    EXPECT_TRUE(static_cast<bool>(fields)) << path << ":" << number << ": '" << text << "'";
    EXPECT_FALSE(fields >> extra) << path << ":" << number << ": more than 4 fields";
    EXPECT_EQ(id_text.find_first_not_of("0123456789"), std::string::npos) << path << ":" << number;
    l.id = std::stoll(id_text);
    lines.push_back(l);
  }
  return lines;
}

TEST(TrackCommand, WritesIdTimeXYTracksOnARealSlice) {
  TempDir dir;
  const std::string out = dir.file("tracks.txt");
  const auto result = runAsynevo("track --dataset " + dataPath("ecd/shapes_rotation") + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("features          "), std::string::npos) << result.output;
  const std::vector<Line> lines = readTracks(out);
  ASSERT_GE(lines.size(), 50u) << result.output;  // docs/frontend.md: 75 measurements of 13 tracks

  // Times inside the slice's span (2.097134001 .. 2.195729000 s), raw pixels inside the 240x180 sensor.
  std::map<int64_t, int> count;
  std::vector<int64_t> order;  // ids in order of first appearance
  std::set<int64_t> closed;    // ids whose block of lines has ended
  int64_t previous_id = -1;
  double previous_t = 0;
  for (const Line& l : lines) {
    EXPECT_GE(l.t, 2.097134001 - 1e-9);
    EXPECT_LE(l.t, 2.195729000 + 1e-9);
    EXPECT_GE(l.x, 0.0);
    EXPECT_LE(l.x, 239.0);
    EXPECT_GE(l.y, 0.0);
    EXPECT_LE(l.y, 179.0);
    if (l.id != previous_id) {
      EXPECT_EQ(closed.count(l.id), 0u) << "the lines of feature " << l.id << " are not together";
      if (previous_id >= 0) closed.insert(previous_id);
      order.push_back(l.id);
    } else {
      EXPECT_GE(l.t, previous_t) << "time goes back within feature " << l.id;
    }
    ++count[l.id];
    previous_id = l.id;
    previous_t = l.t;
  }
  ASSERT_GE(order.size(), 5u);
  for (std::size_t i = 1; i < order.size(); ++i)
    EXPECT_LT(order[i - 1], order[i]) << "ids must increase in order of first appearance";
  EXPECT_NE(result.output.find("wrote             " + std::to_string(lines.size()) + " lines, " +
                               std::to_string(order.size()) + " tracks"),
            std::string::npos)
      << result.output;
}

TEST(TrackCommand, SameInputSameOutput) {
  TempDir dir;
  const std::string args = "track --dataset " + dataPath("ecd/dynamic_rotation") + " --out ";
  ASSERT_EQ(runAsynevo(args + dir.file("a.txt")).exit_code, 0);
  ASSERT_EQ(runAsynevo(args + dir.file("b.txt")).exit_code, 0);
  std::ifstream a(dir.file("a.txt")), b(dir.file("b.txt"));
  const std::string ta((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
  const std::string tb((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(ta.empty());
  EXPECT_EQ(ta, tb);
}

TEST(TrackCommand, BadInputExitsWithOneAndNamesFileAndLine) {
  struct Case {
    const char* content;
    const char* message;
  };
  const Case cases[] = {
      {"0.1 1 2 1\n0.2 1 2\n", "events.txt:2: expected 4 fields 't x y p', found 3 (truncated line?)"},
      {"0.1 1 2 1\n0.2 250 2 1\n", "events.txt:2: pixel (250, 2) is outside the 240x180 sensor"},
      {"0.1 1 2 1\n0.15 1 2 1\n0.2 1 2 7\n", "events.txt:3: polarity 7 is not one of 0, 1, -1"},
      {"0.3 1 2 1\n0.2 1 2 1\n", "events.txt:2: time goes backwards by 100000000 ns"},
  };
  for (const auto& c : cases) {
    TempDir dir;
    dir.write("events.txt", c.content);
    const auto result = runAsynevo("track --dataset " + dir.path().string() + " --out " + dir.file("t.txt"));
    EXPECT_EQ(result.exit_code, 1) << c.content;
    EXPECT_NE(result.output.find("asynevo: error: " + dir.path().string() + "/" + c.message),
              std::string::npos)
        << "expected '" << c.message << "' in:\n"
        << result.output;
  }
}

TEST(TrackCommand, MissingDatasetExitsWithOne) {
  TempDir dir;
  const auto result = runAsynevo("track --dataset " + dir.file("nothing") + " --out " + dir.file("t.txt"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find(dir.file("nothing") + ": no such file or folder"), std::string::npos)
      << result.output;
  EXPECT_NE(runAsynevo("track --out " + dir.file("t.txt")).exit_code, 0);  // --dataset is required
}

TEST(TrackCommand, EvalNeedsASimulatedDataset) {
  TempDir dir;
  const auto result =
      runAsynevo("track --eval --dataset " + dataPath("ecd/shapes_rotation") + " --out " + dir.file("t.txt"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("--eval needs a folder written by 'asynevo simulate'"), std::string::npos)
      << result.output;
}

TEST(TrackCommand, EvalReportsTheTrackErrorOnASimulatedFolder) {
  TempDir dir;
  const std::string sim = dir.file("sim");
  ASSERT_EQ(runAsynevo("simulate --scene shapes --motion 6dof --duration 0.5 --out " + sim).exit_code, 0);
  const auto result = runAsynevo("track --eval --dataset " + sim + " --out " + dir.file("t.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto at = result.output.find("track error");
  ASSERT_NE(at, std::string::npos) << result.output;
  // "track error       N tracks, M errors: median X px, ..."
  const auto median_at = result.output.find("median ", at);
  ASSERT_NE(median_at, std::string::npos);
  const double median = std::stod(result.output.substr(median_at + 7));
  EXPECT_LE(median, 1.0) << result.output;
  EXPECT_FALSE(readTracks(dir.file("t.txt")).empty());
}

}  // namespace
}  // namespace asynevo
