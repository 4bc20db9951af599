// simulate → run → eval on a short sequence, and offline determinism (DESIGN.md §7).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "../pipeline/sim_sequence.hpp"
#include "cli_test_util.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::runAsynevo;
using TempDir = testing::UniqueTempDir;

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The number after `"key": ` in the first object named `object` of a JSON text (eval.json layout).
double jsonNumber(const std::string& json, const std::string& object, const std::string& key) {
  const std::size_t at = json.find("\"" + object + "\"");
  if (at == std::string::npos) return -1;
  std::smatch m;
  const std::string tail = json.substr(at);
  if (!std::regex_search(tail, m, std::regex("\"" + key + "\": *([-0-9.eE+]+)"))) return -1;
  return std::stod(m[1].str());
}

// 3 s of the 'boxes' scene with the 6dof preset (about 2.5 M events): ~8 s to simulate, ~5 s per run.
constexpr const char* kScene = "boxes";
constexpr const char* kMotion = "6dof";
constexpr double kDuration = 3.0;

TEST(RunEndToEnd, SimulateRunEvalReachesTheMeasuredAccuracy) {
  std::string error;
  const std::string data = testing::simulatedSequence(kScene, kMotion, kDuration, error);
  ASSERT_FALSE(data.empty()) << error;
  const TempDir dir;
  const std::string out = dir.file("run");
  const auto run = runAsynevo("run --dataset " + data + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto ev = runAsynevo("eval --gt " + out + "/stamped_groundtruth.txt --est " + out +
                             "/stamped_traj_estimate.txt --out " + out);
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  const std::string json = readFile(out + "/eval.json");
  const double ate = jsonNumber(json, "ate", "rmse");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(json, m, std::regex("\"gt_path_length_m\": *([0-9.eE+-]+)"))) << json;
  const double path_length = std::stod(m[1].str());
  ASSERT_GT(ate, 0) << json;
  // Measured (2025-11, this commit's estimator defaults): ATE 0.0256 m on a 0.993 m path (2.6 %).
  // Threshold 5 % of the ground-truth path length.
  EXPECT_LT(ate, 0.05 * path_length) << ev.output;
  // The estimate covers the sequence without gaps: knots every knot_dt from initialization to the end.
  const std::string traj = readFile(out + "/stamped_traj_estimate.txt");
  std::istringstream in(traj);
  std::string line;
  double previous = -1, max_gap = 0, last = 0;
  int knots = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const double t = std::stod(line.substr(0, line.find(' ')));
    if (previous >= 0) max_gap = std::max(max_gap, t - previous);
    previous = last = t;
    ++knots;
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
  }
  EXPECT_GT(knots, 40);
  EXPECT_LT(max_gap, 0.101);
  EXPECT_GT(last, kDuration - 0.2);
}

TEST(RunEndToEnd, TwoOfflineRunsWriteIdenticalFiles) {
  std::string error;
  const std::string data = testing::simulatedSequence(kScene, kMotion, kDuration, error);
  ASSERT_FALSE(data.empty()) << error;
  const TempDir dir;
  const auto a = runAsynevo("run --dataset " + data + " --out " + dir.file("a"));
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto b = runAsynevo("run --dataset " + data + " --out " + dir.file("b"));
  ASSERT_EQ(b.exit_code, 0) << b.output;
  for (const char* f : {"stamped_traj_estimate.txt", "tracks.txt", "backend_feed.txt", "velocities.txt",
                        "landmarks.ply", "config.yaml"}) {
    const std::string fa = readFile(dir.file(std::string("a/") + f)),
                      fb = readFile(dir.file(std::string("b/") + f));
    EXPECT_GT(fa.size(), 100u) << f;
    EXPECT_TRUE(fa == fb) << f << " differs between two runs";
  }
}

// A gap in the events ends the segment; the estimator starts again after it, and eval aligns each
// segment on its own (docs/method/tracking_loss.md). In this scene the restart after the gap begins in
// the depth-reversed basin (its knots 113-118 deg from the true direction of travel); the direction
// audit ends that segment as a reversal and the estimator starts once more.
TEST(RunEndToEnd, AGapInTheEventsGivesTwoSegmentsThatEvalScoresApart) {
  std::string error;
  const std::string data = testing::simulatedSequence(kScene, kMotion, kDuration, error);
  ASSERT_FALSE(data.empty()) << error;
  const TempDir dir;
  const std::string gapped = dir.file("gapped");
  std::filesystem::create_directories(gapped);
  for (const char* f : {"calib.txt", "groundtruth.txt"})
    std::filesystem::copy_file(data + "/" + f, gapped + "/" + f);
  {
    std::ifstream in(data + "/events.txt");
    std::ofstream out(gapped + "/events.txt");
    std::string line;
    while (std::getline(in, line)) {
      const double t = std::stod(line.substr(0, line.find(' ')));
      if (t < 1.4 || t >= 1.8) out << line << '\n';  // 400 ms without events
    }
  }
  const std::string out = dir.file("run");
  const auto run = runAsynevo("run --dataset " + gapped + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("segments        3:"), std::string::npos) << run.output;
  const std::string segments = readFile(out + "/segments.txt");
  std::istringstream lines(segments);
  std::string line;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string f; fields >> f;) row.push_back(f);
    rows.push_back(row);
  }
  ASSERT_EQ(rows.size(), 3u) << segments;
  EXPECT_EQ(rows[0][4], "event_gap");
  EXPECT_LT(std::stod(rows[0][2]), 1.4);
  EXPECT_GE(std::stod(rows[1][1]), 1.8);
  EXPECT_EQ(rows[1][4], "reversal");
  EXPECT_EQ(rows[2][4], "end_of_stream");
  const auto ev = runAsynevo("eval --gt " + out + "/stamped_groundtruth.txt --est " + out +
                             "/stamped_traj_estimate.txt --out " + out);
  ASSERT_EQ(ev.exit_code, 0) << ev.output;
  EXPECT_NE(ev.output.find("per segment; 3 segments cover"), std::string::npos) << ev.output;
  const std::string json = readFile(out + "/eval.json");
  const double coverage = jsonNumber(json, "coverage", "coverage");
  EXPECT_GT(coverage, 0.4) << json;
  EXPECT_LT(coverage, 0.9) << json;
}

// Overload (issue 23): replayed five times faster than real time, the frontend and the backend fall
// behind. The run still ends normally with a valid trajectory; the backend lag and how far the pacing
// fell behind are reported; the queue stays within its capacity; no event is dropped.
TEST(RunEndToEnd, FiveTimesFasterThanRealTimeEndsNormallyAndReportsTheLag) {
  std::string error;
  const std::string data = testing::simulatedSequence(kScene, kMotion, kDuration, error);
  ASSERT_FALSE(data.empty()) << error;
  const TempDir dir;
  const std::string out = dir.file("run");
  const auto run = runAsynevo("run --dataset " + data + " --realtime --speed 5 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("backend lag"), std::string::npos) << run.output;
  const std::string stats = readFile(out + "/stats.json");
  const double capacity = jsonNumber(stats, "pipeline", "queue_capacity_chunks");
  const double high_water = jsonNumber(stats, "pipeline", "queue_high_water_chunks");
  ASSERT_GT(capacity, 0) << stats;
  EXPECT_LE(high_water, capacity);
  EXPECT_GE(jsonNumber(stats, "pipeline", "backend_lag_max_s"), 0.0);
  EXPECT_GE(jsonNumber(stats, "pipeline", "pacing_max_behind_s"), 0.0);
  // Every event was processed: the summary's count equals the offline run's.
  const auto offline = runAsynevo("run --dataset " + data + " --out " + dir.file("offline"));
  ASSERT_EQ(offline.exit_code, 0) << offline.output;
  const std::regex events_line("events +([0-9]+) over");
  std::smatch a, b;
  ASSERT_TRUE(std::regex_search(run.output, a, events_line)) << run.output;
  ASSERT_TRUE(std::regex_search(offline.output, b, events_line)) << offline.output;
  EXPECT_EQ(a[1].str(), b[1].str());
  // A valid trajectory: finite, time-ordered knots that cover the sequence after the start.
  std::istringstream in(readFile(out + "/stamped_traj_estimate.txt"));
  std::string line;
  double previous = -1;
  int knots = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> v;
    for (double x; fields >> x;) v.push_back(x);
    ASSERT_EQ(v.size(), 8u) << line;
    for (const double x : v) ASSERT_TRUE(std::isfinite(x)) << line;
    EXPECT_GT(v[0], previous) << line;
    previous = v[0];
    ++knots;
  }
#if defined(__SANITIZE_THREAD__)
  // Under ThreadSanitizer (scripts/sanitize_thread.sh) the code runs 5-20 times slower against the same
  // wall clock, so the real-time solver cap leaves fewer knots (40 in one run on 2026-11-26). That run
  // checks the two threads for races; how much trajectory a slowed-down run keeps is not its question.
  EXPECT_GT(knots, 0);
#else
  EXPECT_GT(knots, 40);
#endif
}

}  // namespace
}  // namespace asynevo
