#include "asynevo/pipeline/run_folder.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "asynevo/core/error.hpp"
#include "asynevo/eval/timing.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "io_test_util.hpp"

namespace asynevo::pipeline {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

backend::Knot knot(int64_t t_ns, double x) {
  backend::Knot k;
  k.t_ns = t_ns;
  k.pose = {x, 2.0, 3.0, 0.0, 0.0, std::sin(0.1), std::cos(0.1)};
  k.velocity = {0.5, 0.0, -0.5, 0.01, 0.02, 0.03};
  return k;
}

TEST(RunFolderWriter, WritesTrajectoryVelocitiesTracksFeedTimingAndLandmarksThatReadBack) {
  const asynevo::testing::TempDir dir;
  const std::string out = dir.file("run");
  {
    RunFolderWriter writer(out);
    writer.onMarker(1'499'000'000);
    writer.onMeasurement({7, 1'500'000'000, 10.25f, 20.5f, 0.1f, 0.2f});
    writer.onMeasurement({8, 1'500'100'000, 11.0f, 21.0f, 0.1f, 0.2f});
    writer.onMarker(1'500'000'000);
    writer.onMeasurement({9, 1'500'200'000, 123.456789f, 0.1f, 0.1f, 0.2f});  // a sub-pixel float
    writer.onFinalKnots({knot(1'000'000'000, 1.0), knot(1'050'000'000, 1.25)});
    // Written knots are on disk before close() (a crash leaves a partial but valid file).
    EXPECT_EQ(readTumTrajectory(writer.path("stamped_traj_estimate.txt")).size(), 2u);
    writer.onFinalKnots({knot(1'100'000'000, 1.5)});
    backend::UpdateRecord r;
    r.event_t_ns = 1'050'000'000;
    r.window_knots = 12;
    r.total_ms = 4.5;
    r.solve_ms = 3.0;
    writer.onUpdateRecords({r});
    r.total_ms = 2.5;
    writer.onUpdateRecords({r});
    // Landmarks come in batches over the run; landmarks.ply counts them all in its header.
    writer.onLandmarks({{1, Eigen::Vector3d(1, 2, 3), 9}});
    writer.onLandmarks({{2, Eigen::Vector3d(-1, 0.5, 4), 5}});
    EXPECT_EQ(writer.landmarksWritten(), 2u);
    writer.close();
    EXPECT_EQ(writer.knotsWritten(), 3u);
    EXPECT_EQ(writer.measurementsWritten(), 3u);
    const UpdateTimeStats s = writer.updateTimeStats();
    EXPECT_EQ(s.updates, 2u);
    EXPECT_DOUBLE_EQ(s.median_ms, 3.5);
    EXPECT_DOUBLE_EQ(s.max_ms, 4.5);
    EXPECT_EQ(s.max_window_knots, 12);
  }
  const StampedTrajectory traj = readTumTrajectory(out + "/stamped_traj_estimate.txt");
  ASSERT_EQ(traj.size(), 3u);
  EXPECT_EQ(traj[2].t_ns, 1'100'000'000);
  EXPECT_DOUBLE_EQ(traj[2].p_w_c.x(), 1.5);
  EXPECT_NEAR(traj[0].q_w_c.z(), std::sin(0.1), 1e-15);
  const auto twists = readVelocities(out + "/velocities.txt");
  ASSERT_EQ(twists.size(), 3u);
  EXPECT_DOUBLE_EQ(twists[1].w_c.z(), 0.03);
  // Pixels as the shortest text that reads back as the same float (a replay sees what the backend saw).
  const std::string tracks = readFile(out + "/tracks.txt");
  EXPECT_NE(tracks.find("\n7 1.500000000 10.25 20.5\n8 1.500100000 11 21\n9 1.500200000 "), std::string::npos)
      << tracks;
  std::istringstream last(tracks.substr(tracks.rfind("\n9 ") + 1));
  int64_t id = 0;
  std::string t;
  float x = 0, y = 0;
  last >> id >> t >> x >> y;
  EXPECT_EQ(x, 123.456789f);
  EXPECT_EQ(y, 0.1f);
  // Each marker with the number of tracks.txt lines taken before it (the backend's call sequence).
  const std::string feed = readFile(out + "/backend_feed.txt");
  EXPECT_NE(feed.find("\n1.499000000 0\n1.500000000 2\n"), std::string::npos) << feed;
  const eval::TimingStats timing = eval::readTimingStats(out + "/timing.csv");
  EXPECT_EQ(timing.updates, 2u);
  EXPECT_TRUE(timing.has_total);
  const std::string ply = readFile(out + "/landmarks.ply");
  EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex 2\n"), std::string::npos);
  EXPECT_NE(ply.find("end_header\n1 2 3 9 1\n-1 0.5 4 5 2\n"), std::string::npos);
}

TEST(RunFolderWriter, TimingRowsAreOnDiskBeforeClose) {
  // A run stopped by a time limit (killed, close() never called) must keep its timing rows.
  const asynevo::testing::TempDir dir;
  RunFolderWriter writer(dir.file("run"));
  backend::UpdateRecord r;
  r.event_t_ns = 2'000'000'000;
  r.window_knots = 5;
  r.total_ms = 7.25;
  writer.onUpdateRecords({r});
  r.event_t_ns = 2'050'000'000;
  r.total_ms = 9.5;
  writer.onUpdateRecords({r});
  const std::string csv = readFile(writer.path("timing.csv"));
  EXPECT_EQ(csv.rfind(std::string(kTimingCsvHeader) + "\n", 0), 0u);
  EXPECT_NE(csv.find("\n2.050000000,5,"), std::string::npos);
  EXPECT_EQ(csv.back(), '\n');  // complete rows only
  const eval::TimingStats timing = eval::readTimingStats(writer.path("timing.csv"));
  EXPECT_EQ(timing.updates, 2u);
  writer.close();
}

TEST(RunFolderWriter, ReportsAFolderItCannotCreate) {
  const asynevo::testing::TempDir dir;
  const std::string file = dir.write("plain_file", "x");
  EXPECT_THROW({ RunFolderWriter writer(file + "/sub"); }, Error);
}

TEST(JsonObject, EscapesStringsNestsObjectsAndWritesNonFiniteAsNull) {
  JsonObject inner;
  inner.add("n", static_cast<uint64_t>(3)).add("ok", true);
  JsonObject root;
  root.add("text", "a \"quoted\"\\ line\nnext\x01")
      .add("x", 0.5)
      .add("nan", std::nan(""))
      .add("neg", static_cast<int64_t>(-4))
      .addObject("inner", inner)
      .addObject("empty", JsonObject());
  EXPECT_EQ(root.str(),
            "{\n"
            "  \"text\": \"a \\\"quoted\\\"\\\\ line\\nnext\\u0001\",\n"
            "  \"x\": 0.5,\n"
            "  \"nan\": null,\n"
            "  \"neg\": -4,\n"
            "  \"inner\": {\n"
            "    \"n\": 3,\n"
            "    \"ok\": true\n"
            "  },\n"
            "  \"empty\": {}\n"
            "}");
}

}  // namespace
}  // namespace asynevo::pipeline
