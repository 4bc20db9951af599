// A ROS bag used alone: events, a pose topic (ground truth) and a CameraInfo topic (calibration), through
// 'asynevo info', 'run' and 'eval' as a user runs them (docs/reference/formats_rosbag.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_util.hpp"
#include "io_test_util.hpp"
#include "rosbag_fixture.hpp"

namespace asynevo {
namespace {

namespace bag = testing::bag;
using testing::runAsynevo;
using testing::TempDir;

constexpr uint64_t kT0 = 1'600'000'000'000'000'000ull;  // ns
constexpr int kPoses = 31;                               // 100 Hz over the 300 ms of events

const bag::Connection kDvs{0, "/dvs/events", bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
const bag::Connection kPose{1, "/optitrack/davis", bag::kPoseStampedType, bag::kPoseStampedMd5, "(definition)"};
const bag::Connection kInfo{2, "/dvs/camera_info", bag::kCameraInfoType, bag::kCameraInfoMd5, "(definition)"};
const bag::Connection kOdom{3, "/odom", bag::kOdometryType, bag::kOdometryMd5, "(definition)"};

/// 300 ms of events (30 messages of 10 ms, 500 events each, a pattern over the 240x180 sensor), poses at
/// 100 Hz on a curve, one CameraInfo of `info_width` x 180; with `odometry` also an Odometry topic.
std::string recording(uint32_t info_width = 240, bool odometry = false) {
  std::vector<bag::Chunk> chunks;
  uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  std::vector<bag::Message> messages{
      {2, kT0, bag::cameraInfo(info_width, 180, "plumb_bob", {-0.3, 0.1, 0.001, 0.0005, 0.0}, 199.0, 198.0, 120.0, 90.0)}};
  for (int k = 0; k < 30; ++k) {
    std::vector<bag::DvsEvent> events;
    for (int i = 0; i < 500; ++i) {
      const uint32_t r = next() >> 8;
      events.push_back({static_cast<uint16_t>(r % 240), static_cast<uint16_t>((r / 240) % 180),
                        kT0 + uint64_t(k) * 10'000'000 + uint64_t(i) * 20'000, (r & 1) != 0});
    }
    messages.push_back({0, events.front().t_ns, bag::eventArray(240, 180, events)});
  }
  for (int i = 0; i < kPoses; ++i) {
    bag::Pose p;
    p.px = 0.1 * std::sin(0.2 * i);
    p.py = 0.02 * i;
    p.pz = 0.05 * std::cos(0.1 * i);
    p.qz = std::sin(0.01 * i);
    p.qw = std::cos(0.01 * i);
    const uint64_t t = kT0 + uint64_t(i) * 10'000'000;
    messages.push_back({1, t, bag::poseStamped(t, p)});
    if (odometry) messages.push_back({3, t, bag::odometry(t, p)});
  }
  // Two chunks, as a recorder splits a recording.
  const std::size_t half = messages.size() / 2;
  chunks.emplace_back(std::vector<bag::Message>(messages.begin(), messages.begin() + half));
  chunks.emplace_back(std::vector<bag::Message>(messages.begin() + half, messages.end()));
  std::vector<bag::Connection> connections{kDvs, kPose, kInfo};
  if (odometry) connections.push_back(kOdom);
  return bag::buildBag(connections, chunks);
}

std::size_t lineCount(const std::string& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

TEST(RosbagCli, InfoTakesGroundTruthAndCalibrationFromTheBag) {
  TempDir dir;
  const std::string path = dir.write("recording.bag", recording());
  const auto result = runAsynevo("info --dataset " + path);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("calibration   " + path + " (topic /dvs/camera_info)\n"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("fx=199"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("ground truth  " + path + " (topic /optitrack/davis)\n              31 poses, "
                               "1600000000.000000000 .. 1600000000.300000000 s, 30 inside the event span"),
            std::string::npos)
      << result.output;
  // A groundtruth.txt beside the bag wins, and info says which topic is not used.
  dir.write("groundtruth.txt", "1600000000.0 0 0 0 0 0 0 1\n1600000000.1 1 0 0 0 0 0 1\n");
  const auto beside = runAsynevo("info --dataset " + dir.path().string());
  ASSERT_EQ(beside.exit_code, 0) << beside.output;
  EXPECT_NE(beside.output.find("groundtruth.txt\n              2 poses"), std::string::npos) << beside.output;
  EXPECT_NE(beside.output.find("note: the bag's pose topic(s) /optitrack/davis not used: the file beside the bag wins"),
            std::string::npos)
      << beside.output;
  const auto chosen = runAsynevo("info --dataset " + dir.path().string() + " --gt-topic /optitrack/davis");
  EXPECT_NE(chosen.output.find("(topic /optitrack/davis)\n              31 poses"), std::string::npos) << chosen.output;
}

TEST(RosbagCli, TwoPoseTopicsNeedGtTopic) {
  TempDir dir;
  const std::string path = dir.write("two.bag", recording(240, true));
  const auto result = runAsynevo("info --dataset " + path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("the bag has 2 pose topics: /optitrack/davis (geometry_msgs/PoseStamped, 31 messages), "
                               "/odom (nav_msgs/Odometry, 31 messages); choose one with --gt-topic NAME"),
            std::string::npos)
      << result.output;
  // run stops before reading any event, not after the estimate.
  const auto run = runAsynevo("run --dataset " + path + " --out " + dir.file("run"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("choose one with --gt-topic NAME"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("run") + "/stats.json"));
  const auto chosen = runAsynevo("info --dataset " + path + " --gt-topic /odom");
  EXPECT_EQ(chosen.exit_code, 0) << chosen.output;
  EXPECT_NE(chosen.output.find("(topic /odom)\n              31 poses"), std::string::npos) << chosen.output;
}

TEST(RosbagCli, RunAndEvalUseTheBagAlone) {
  TempDir dir;
  const std::string path = dir.write("recording.bag", recording());
  const std::string out = dir.file("run");
  // Random events do not let the estimator start (exit code 1), but the run still reports its sources and
  // writes the ground truth of the event span.
  const auto run = runAsynevo("run --dataset " + path + " --out " + out);
  EXPECT_NE(run.output.find("calibration     " + path + " (topic /dvs/camera_info)\n"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("ground truth    " + path + " (topic /optitrack/davis) (30 poses in the event span "
                            "written)"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(lineCount(out + "/stamped_groundtruth.txt"), 30u);  // the pose at 300 ms is after the last event
  // eval reads the bag's pose topic as the ground truth: the run's copy of it matches exactly.
  const auto eval = runAsynevo("eval --gt " + path + " --gt-topic /optitrack/davis --est " + out +
                               "/stamped_groundtruth.txt --align se3 --velocities none --out " + dir.file("eval"));
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  std::ifstream json(dir.file("eval") + "/eval.json");
  std::stringstream text;
  text << json.rdbuf();
  EXPECT_NE(text.str().find("\"matched\": 30"), std::string::npos) << text.str().substr(0, 600);
}

TEST(RosbagCli, CameraInfoOfAnotherSizeIsAnError) {
  TempDir dir;
  const std::string path = dir.write("recording.bag", recording(346));
  const auto run = runAsynevo("run --dataset " + path + " --out " + dir.file("run"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find(path + ": the camera info of topic /dvs/camera_info is for 346x180 pixels but the events "
                                   "are 240x180 (size from the bag's messages)"),
            std::string::npos)
      << run.output;
  // A calibration file beside the bag wins over the CameraInfo topic.
  dir.write("calib.txt", "199 198 120 90 0 0 0 0 0\n");
  const auto with_file = runAsynevo("info --dataset " + dir.path().string());
  EXPECT_NE(with_file.output.find("calib.txt"), std::string::npos) << with_file.output;
  EXPECT_NE(with_file.output.find("note: the bag's sensor_msgs/CameraInfo topic(s) /dvs/camera_info not used: the file wins "
                                  "(--camera-info-topic NAME reads the bag's)"),
            std::string::npos)
      << with_file.output;
}

// Two CameraInfo topics: the one in the event topic's namespace, or --camera-info-topic.
TEST(RosbagCli, CameraInfoTopicChoice) {
  TempDir dir;
  const bag::Connection rgb{4, "/rgb/camera_info", bag::kCameraInfoType, bag::kCameraInfoMd5, "(definition)"};
  std::vector<bag::DvsEvent> events;
  for (int i = 0; i < 100; ++i)
    events.push_back({static_cast<uint16_t>(i % 240), static_cast<uint16_t>(i % 180), kT0 + uint64_t(i) * 1000, true});
  const std::string path = dir.write(
      "two_cameras.bag",
      bag::buildBag({kDvs, kInfo, rgb},
                    {bag::Chunk{{{0, kT0, bag::eventArray(240, 180, events)},
                                 {2, kT0, bag::cameraInfo(240, 180, "plumb_bob", {}, 199.0, 198.0, 120.0, 90.0)},
                                 {4, kT0, bag::cameraInfo(640, 480, "plumb_bob", {}, 500.0, 500.0, 320.0, 240.0)}}}}));
  const auto info = runAsynevo("info --dataset " + path);
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("calibration   " + path + " (topic /dvs/camera_info)"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("note: chosen among 2 CameraInfo topics as the one in the namespace /dvs of the event "
                             "topic /dvs/events"),
            std::string::npos)
      << info.output;
  const auto named = runAsynevo("info --dataset " + path + " --camera-info-topic /rgb/camera_info");
  ASSERT_EQ(named.exit_code, 0) << named.output;
  EXPECT_NE(named.output.find("calibration   " + path + " (topic /rgb/camera_info)"), std::string::npos)
      << named.output;
  EXPECT_NE(named.output.find("warning: the camera info is for 640x480 pixels but the events are 240x180"),
            std::string::npos)
      << named.output;
  const auto missing = runAsynevo("info --dataset " + path + " --camera-info-topic /nope");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("the bag has no topic '/nope' (--camera-info-topic)"), std::string::npos)
      << missing.output;
  const auto both = runAsynevo("run --dataset " + path + " --calib " + dir.file("calib.txt") +
                               " --camera-info-topic /rgb/camera_info --out " + dir.file("run"));
  EXPECT_EQ(both.exit_code, 1) << both.output;
  EXPECT_NE(both.output.find("both name the calibration: give one of them"), std::string::npos) << both.output;
}

TEST(RosbagCli, InfoShowsBothClocksOfAnEventPacketBag) {
  const std::string path = testing::sharedFormatSample("rosbag/test_events_1.bag");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (the shared data folder is missing)";
  const auto result = runAsynevo("info --dataset " + path);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("clocks        events in the camera's clock (first event "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("the first packet's header stamp (ROS time) is "), std::string::npos) << result.output;
}

// An EventPacket bag: events on the camera's clock (from 1 s), poses on ROS time (from kT0), the first
// packet stamped kT0 + 2 ms (the driver's latency). --gt-camera-clock shifts the poses by the first
// packet's stamp minus its first event's time.
TEST(RosbagCli, GtCameraClockShiftsAnEventPacketBagsPosesOntoItsEvents) {
  const bag::Connection packets{0, "/event_camera/events", bag::kEventPacketType, bag::kEventPacketMd5, "(definition)"};
  std::vector<bag::Message> messages{
      {2, kT0, bag::cameraInfo(240, 180, "plumb_bob", {0.0, 0.0, 0.0, 0.0, 0.0}, 200.0, 200.0, 120.0, 90.0)}};
  // EVT 3.0 (docs/reference/formats_prophesee.md): time high (bits 23..12 of the µs time), time low, y,
  // then x with its polarity. 300 packets of 1 ms, 20 events each, camera time 1.000 s .. 1.299 s.
  auto word = [](uint32_t w) { return bag::u16(w); };
  uint32_t state = 7;
  for (int k = 0; k < 300; ++k) {
    const uint32_t t_us = 1'000'000 + uint32_t(k) * 1000;
    std::string payload = word(0x8000 | ((t_us >> 12) & 0xFFF)) + word(0x6000 | (t_us & 0xFFF));
    for (int i = 0; i < 20; ++i) {
      state = state * 1664525u + 1013904223u;
      payload += word(0x0000 | ((state >> 8) % 180)) + word(0x2000 | (((state >> 20) & 1) << 11) | ((state >> 12) % 240));
    }
    const uint64_t stamp = kT0 + 2'000'000 + uint64_t(k) * 1'000'000;
    messages.push_back({0, stamp, bag::eventPacket(240, 180, "evt3", payload, uint32_t(k), false, stamp)});
  }
  for (int i = 0; i < kPoses; ++i) {
    bag::Pose p;
    p.py = 0.02 * i;
    const uint64_t t = kT0 + uint64_t(i) * 10'000'000;
    messages.push_back({1, t, bag::poseStamped(t, p)});
  }
  std::stable_sort(messages.begin(), messages.end(), [](const auto& a, const auto& b) { return a.time_ns < b.time_ns; });
  TempDir dir;
  const std::string path =
      dir.write("packets.bag", bag::buildBag({packets, kPose, kInfo}, {bag::Chunk(std::move(messages))}));

  const auto plain = runAsynevo("run --dataset " + path + " --out " + dir.file("plain"));
  EXPECT_NE(plain.output.find("no ground-truth pose within the event time span"), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find("--gt-camera-clock shifts the poses"), std::string::npos) << plain.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("plain") + "/stamped_groundtruth.txt"));

  const std::string out = dir.file("shifted");
  const auto shifted = runAsynevo("run --dataset " + path + " --gt-camera-clock --out " + out);
  // ROS time of the first event kT0 + 2 ms, its camera time 1 s: the pose at kT0 lands at 0.998 s.
  EXPECT_NE(shifted.output.find("ground truth    " + path + " (topic /optitrack/davis), shifted by "),
            std::string::npos)
      << shifted.output;
  std::ifstream gt(out + "/stamped_groundtruth.txt");
  std::string line;
  while (std::getline(gt, line) && (line.empty() || line[0] == '#')) {
  }
  EXPECT_EQ(line.substr(0, 12), "1.008000000 ") << line;  // the first pose inside the events' span
  EXPECT_EQ(lineCount(out + "/stamped_groundtruth.txt"), 30u);  // 1.008 .. 1.298 s
  std::ifstream json(out + "/stats.json");
  std::stringstream text;
  text << json.rdbuf();
  const std::string key = "\"groundtruth_shift_s\": ";
  const std::size_t at = text.str().find(key);
  ASSERT_NE(at, std::string::npos);
  EXPECT_NEAR(std::strtod(text.str().c_str() + at + key.size(), nullptr), 1.0 - (kT0 * 1e-9 + 0.002), 1e-6);

  // Not a bag: a usage error before anything is read.
  const auto aevt = dir.file("events.aevt");
  ASSERT_EQ(runAsynevo("convert --dataset " + path + " --out " + aevt).exit_code, 0);
  const auto wrong = runAsynevo("run --dataset " + aevt + " --calib " + dir.write("calib.txt", "200 200 120 90 0 0 0 0 0\n") +
                                " --gt-camera-clock --out " + dir.file("wrong"));
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.output.find("--gt-camera-clock applies to ROS bags"), std::string::npos) << wrong.output;
}

}  // namespace
}  // namespace asynevo
