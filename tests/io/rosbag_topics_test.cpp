// Ground truth (pose topics) and calibration (CameraInfo topics) read from ROS1 bags built byte by byte
// from the specification (rosbag_fixture.hpp); the precedence rules of io/dataset.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/rosbag_topics.hpp"
#include "io_test_util.hpp"
#include "rosbag_fixture.hpp"

namespace asynevo {
namespace {

namespace bag = testing::bag;
using testing::TempDir;

constexpr uint64_t kT0 = 1'600'000'000'000'000'000ull;  // ns, ROS time

const bag::Connection kDvs{0, "/dvs/events", bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
const bag::Connection kPose{1, "/optitrack/pose", bag::kPoseStampedType, bag::kPoseStampedMd5, "(definition)"};
const bag::Connection kOdom{2, "/odom", bag::kOdometryType, bag::kOdometryMd5, "(definition)"};
const bag::Connection kTf{3, "/vicon/camera", bag::kTransformStampedType, bag::kTransformStampedMd5, "(definition)"};
const bag::Connection kInfo{4, "/dvs/camera_info", bag::kCameraInfoType, bag::kCameraInfoMd5, "(definition)"};

bag::Message events(int first, int count) {
  std::vector<bag::DvsEvent> e;
  for (int i = first; i < first + count; ++i)
    e.push_back({static_cast<uint16_t>(i % 240), static_cast<uint16_t>(i % 180), kT0 + uint64_t(i) * 1000, i % 2 == 0});
  return {0, kT0 + uint64_t(first) * 1000, bag::eventArray(240, 180, e)};
}

/// Pose i: position (i, 2i, -i) / 10, a rotation of 0.1 i rad about z, stamped kT0 + 10 ms * i.
bag::Pose poseAt(int i) {
  bag::Pose p;
  p.px = i / 10.0;
  p.py = 2 * i / 10.0;
  p.pz = -i / 10.0;
  p.qz = std::sin(0.05 * i);
  p.qw = std::cos(0.05 * i);
  return p;
}
uint64_t stampAt(int i) { return kT0 + uint64_t(i) * 10'000'000; }

using Encode = std::function<std::string(uint64_t, const bag::Pose&, uint32_t)>;
std::vector<bag::Message> poseMessages(uint32_t conn, const Encode& encode, int count) {
  std::vector<bag::Message> m;
  for (int i = 0; i < count; ++i) m.push_back({conn, stampAt(i) + 777, encode(stampAt(i), poseAt(i), uint32_t(i))});
  return m;
}

void expectPoses(const StampedTrajectory& poses, int count) {
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const bag::Pose p = poseAt(i);
    EXPECT_EQ(poses[i].t_ns, static_cast<int64_t>(stampAt(i))) << i;  // the header stamp, not the record time
    EXPECT_DOUBLE_EQ(poses[i].p_w_c.x(), p.px);
    EXPECT_DOUBLE_EQ(poses[i].p_w_c.y(), p.py);
    EXPECT_DOUBLE_EQ(poses[i].p_w_c.z(), p.pz);
    EXPECT_NEAR(poses[i].q_w_c.z(), p.qz, 1e-15);
    EXPECT_NEAR(poses[i].q_w_c.w(), p.qw, 1e-15);
  }
}

std::string bagError(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RosbagGroundTruth, PoseStampedTopic) {
  TempDir dir;
  std::vector<bag::Message> chunk1{events(0, 50)};
  for (const bag::Message& m : poseMessages(1, bag::poseStamped, 5)) chunk1.push_back(m);
  const std::string path = dir.write("gt.bag", bag::buildBag({kDvs, kPose}, {bag::Chunk{chunk1}, bag::Chunk{{events(50, 5)}}}));
  const auto gt = readRosbagGroundTruth(path);
  ASSERT_TRUE(gt.has_value());
  EXPECT_EQ(gt->topic, "/optitrack/pose");
  EXPECT_EQ(gt->type, bag::kPoseStampedType);
  expectPoses(gt->poses, 5);
  EXPECT_EQ(rosbagPoseTopics(path), std::vector<std::string>{"/optitrack/pose"});
}

TEST(RosbagGroundTruth, TransformStampedAndOdometryTopics) {
  TempDir dir;
  const std::string tf = dir.write("tf.bag", bag::buildBag({kDvs, kTf}, {bag::Chunk{poseMessages(3, bag::transformStamped, 7)}}));
  const auto a = readRosbagGroundTruth(tf);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->type, bag::kTransformStampedType);
  expectPoses(a->poses, 7);
  const std::string odom =
      dir.write("odom.bag", bag::buildBag({kDvs, kOdom}, {bag::Chunk{poseMessages(2, bag::odometry, 4)}, bag::Chunk{poseMessages(2, bag::odometry, 0)}}));
  const auto b = readRosbagGroundTruth(odom);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->topic, "/odom");
  expectPoses(b->poses, 4);
}

TEST(RosbagGroundTruth, TopicChoice) {
  TempDir dir;
  std::vector<bag::Message> messages = poseMessages(1, bag::poseStamped, 3);
  for (const bag::Message& m : poseMessages(2, bag::odometry, 2)) messages.push_back(m);
  const std::string path = dir.write("two.bag", bag::buildBag({kDvs, kPose, kOdom}, {bag::Chunk{messages}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path); })
                .find("the bag has 2 pose topics: /optitrack/pose (geometry_msgs/PoseStamped, 3 messages), /odom "
                      "(nav_msgs/Odometry, 2 messages); choose one with --gt-topic NAME"),
            std::string::npos)
      << bagError([&] { readRosbagGroundTruth(path); });
  EXPECT_EQ(readRosbagGroundTruth(path, "/odom")->poses.size(), 2u);
  EXPECT_EQ(readRosbagGroundTruth(path, "/optitrack/pose")->poses.size(), 3u);
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path, "/nope"); }).find("the bag has no topic '/nope' (--gt-topic)"),
            std::string::npos);
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path, "/dvs/events"); })
                .find("topic /dvs/events (--gt-topic) holds dvs_msgs/EventArray messages, not a pose type"),
            std::string::npos);
  // No pose topic: no ground truth, not an error.
  const std::string none = dir.write("none.bag", bag::buildBag({kDvs}, {bag::Chunk{{events(0, 3)}}}));
  EXPECT_FALSE(readRosbagGroundTruth(none).has_value());
  EXPECT_TRUE(rosbagPoseTopics(none).empty());
}

TEST(RosbagGroundTruth, OneChildFrameOfATfTopic) {
  // Each /tf message holds the camera's pose i (parent world) and a robot link's (parent odom), in that
  // order or the reverse.
  const bag::Connection tf{5, "/tf", bag::kTfMessageType, bag::kTfMessageMd5, "(definition)"};
  std::vector<bag::Message> messages;
  for (int i = 0; i < 6; ++i) {
    const bag::Transform camera{stampAt(i), "world", "davis", poseAt(i)};
    const bag::Transform link{stampAt(i) + 5, "odom", "base_link", poseAt(100 + i)};
    messages.push_back({5, stampAt(i) + 777, bag::tfMessage(i % 2 ? std::vector{camera, link} : std::vector{link, camera})});
  }
  for (const bag::Message& m : poseMessages(1, bag::poseStamped, 3)) messages.push_back(m);
  TempDir dir;
  const std::string path = dir.write("tf.bag", bag::buildBag({kDvs, kPose, tf}, {bag::Chunk{messages}}));
  const auto gt = readRosbagGroundTruth(path, "/tf:davis");
  ASSERT_TRUE(gt.has_value());
  EXPECT_EQ(gt->topic, "/tf:davis");
  EXPECT_EQ(gt->type, bag::kTfMessageType);
  expectPoses(gt->poses, 6);
  EXPECT_NO_THROW(checkRosbagPoseTopic(path, "/tf:davis"));
  // Not chosen without being named: the bag's pose topic stays the ground truth.
  EXPECT_EQ(readRosbagGroundTruth(path)->topic, "/optitrack/pose");
  // /tf alone with two child frames lists them.
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path, "/tf"); })
                .find("the tf topic /tf has 2 child frames: base_link (parent odom, 6 poses), davis (parent world, 6 "
                      "poses); choose one with --gt-topic /tf:FRAME"),
            std::string::npos)
      << bagError([&] { readRosbagGroundTruth(path, "/tf"); });
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path, "/tf:camera"); }).find("the tf topic /tf has no transform to frame camera"),
            std::string::npos);
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(path, "/optitrack/pose:davis"); })
                .find("TOPIC:FRAME names a child frame of a tf2_msgs/TFMessage topic, and the bag has no such topic "
                      "'/optitrack/pose'"),
            std::string::npos);
  EXPECT_NE(bagError([&] { checkRosbagPoseTopic(path, "/tf:"); }).find("the frame is empty"), std::string::npos);
  // With one child frame, the topic's name is enough.
  std::vector<bag::Message> only;
  for (int i = 0; i < 4; ++i)
    only.push_back({5, stampAt(i), bag::tfMessage({bag::Transform{stampAt(i), "world", "davis", poseAt(i)}})});
  const std::string one = dir.write("one.bag", bag::buildBag({kDvs, tf}, {bag::Chunk{only}}));
  const auto single = readRosbagGroundTruth(one, "/tf");
  ASSERT_TRUE(single.has_value());
  EXPECT_EQ(single->topic, "/tf:davis");
  expectPoses(single->poses, 4);
}

TEST(RosbagGroundTruth, TfFramesWithTwoParentsOrStampsGoingBackAreErrors) {
  const bag::Connection tf{5, "/tf", bag::kTfMessageType, bag::kTfMessageMd5, "(definition)"};
  TempDir dir;
  const std::string parents = dir.write(
      "parents.bag", bag::buildBag({kDvs, tf}, {bag::Chunk{{{5, stampAt(0), bag::tfMessage({{stampAt(0), "world", "davis", poseAt(0)}})},
                                                            {5, stampAt(1), bag::tfMessage({{stampAt(1), "map", "davis", poseAt(1)}})}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(parents, "/tf:davis"); })
                .find("frame davis has two parents, world and map"),
            std::string::npos)
      << bagError([&] { readRosbagGroundTruth(parents, "/tf:davis"); });
  const std::string back = dir.write(
      "back.bag", bag::buildBag({kDvs, tf}, {bag::Chunk{{{5, stampAt(0), bag::tfMessage({{stampAt(1), "world", "davis", poseAt(1)},
                                                                                          {stampAt(0), "world", "davis", poseAt(0)}})}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(back, "/tf:davis"); }).find("the stamps of frame davis go backwards"),
            std::string::npos);
  // A transform cut short names the field.
  std::string cut = bag::tfMessage({{stampAt(0), "world", "davis", poseAt(0)}});
  cut.resize(cut.size() - 8);
  const std::string short_message = dir.write("short.bag", bag::buildBag({kDvs, tf}, {bag::Chunk{{{5, stampAt(0), cut}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(short_message, "/tf:davis"); }).find("malformed message: the pose needs 8 bytes"),
            std::string::npos)
      << bagError([&] { readRosbagGroundTruth(short_message, "/tf:davis"); });
}

TEST(RosbagGroundTruth, BadMessages) {
  TempDir dir;
  // Another revision (MD5 sum) of the type.
  bag::Connection other = kPose;
  other.md5 = "0123456789abcdef0123456789abcdef";
  const std::string md5 = dir.write("md5.bag", bag::buildBag({other}, {bag::Chunk{poseMessages(1, bag::poseStamped, 2)}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(md5); })
                .find("topic /optitrack/pose has a revision of geometry_msgs/PoseStamped with MD5 sum "
                      "'0123456789abcdef0123456789abcdef'; AsynEVO reads the revision with MD5 sum "
                      "d3812c3cbc69362b77dc0b19b345f8f5"),
            std::string::npos);
  // Message 2 cut short, message 1 too long: errors name the file and the message's index.
  std::vector<bag::Message> cut = poseMessages(1, bag::poseStamped, 3);
  cut[2].data.resize(cut[2].data.size() - 9);
  const std::string short_path = dir.write("short.bag", bag::buildBag({kPose}, {bag::Chunk{cut}}));
  const std::string short_error = bagError([&] { readRosbagGroundTruth(short_path); });
  EXPECT_NE(short_error.find(short_path), std::string::npos) << short_error;
  EXPECT_NE(short_error.find("message 2 of topic /optitrack/pose: malformed message: the pose needs 8 bytes"),
            std::string::npos)
      << short_error;
  std::vector<bag::Message> longer = poseMessages(1, bag::poseStamped, 3);
  longer[1].data += "xyz";
  const std::string long_path = dir.write("long.bag", bag::buildBag({kPose}, {bag::Chunk{longer}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(long_path); })
                .find("message 1 of topic /optitrack/pose: malformed message: 3 bytes are left after the last field of "
                      "geometry_msgs/PoseStamped"),
            std::string::npos);
  // Times going backwards, a zero quaternion, a non-finite position, an odometry message without its twist.
  std::vector<bag::Message> back = poseMessages(1, bag::poseStamped, 3);
  back[2].data = bag::poseStamped(stampAt(0), poseAt(2));
  const std::string back_path = dir.write("back.bag", bag::buildBag({kPose}, {bag::Chunk{back}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(back_path); })
                .find("message 2 of topic /optitrack/pose: the header stamp goes backwards"),
            std::string::npos);
  bag::Pose zero;
  zero.qw = 0;
  const std::string zero_path =
      dir.write("zero.bag", bag::buildBag({kPose}, {bag::Chunk{{{1, kT0, bag::poseStamped(kT0, zero)}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(zero_path); }).find("message 0 of topic /optitrack/pose: zero quaternion"),
            std::string::npos);
  bag::Pose nan;
  nan.py = std::nan("");
  const std::string nan_path =
      dir.write("nan.bag", bag::buildBag({kPose}, {bag::Chunk{{{1, kT0, bag::poseStamped(kT0, nan)}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(nan_path); }).find("non-finite pose"), std::string::npos);
  std::string odom = bag::odometry(kT0, poseAt(0));
  odom.resize(odom.size() - 8);
  const std::string odom_path = dir.write("odom.bag", bag::buildBag({kOdom}, {bag::Chunk{{{2, kT0, odom}}}}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(odom_path); })
                .find("message 0 of topic /odom: malformed message: the pose covariance and the twist needs 624 bytes"),
            std::string::npos)
      << bagError([&] { readRosbagGroundTruth(odom_path); });
  // A pose topic without messages.
  const std::string empty = dir.write("empty.bag", bag::buildBag({kPose}, {}));
  EXPECT_NE(bagError([&] { readRosbagGroundTruth(empty); }).find("the pose topic /optitrack/pose"), std::string::npos);
}

TEST(RosbagCalibration, CameraInfoModels) {
  TempDir dir;
  auto bagWith = [&](const std::string& name, const std::vector<std::string>& infos) {
    std::vector<bag::Message> m{events(0, 5)};
    for (const std::string& info : infos) m.push_back({4, kT0, info});
    return dir.write(name, bag::buildBag({kDvs, kInfo}, {bag::Chunk{m}}));
  };
  const std::vector<double> radtan{-0.37, 0.16, 0.001, -0.0005, 0.02};
  const std::string plumb = bagWith("plumb.bag", {bag::cameraInfo(240, 180, "plumb_bob", radtan, 199.1, 198.5, 121.2, 92.3),
                                                  bag::cameraInfo(240, 180, "plumb_bob", {}, 1, 1, 1, 1)});
  const auto a = readRosbagCalibration(plumb);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->topic, "/dvs/camera_info");
  EXPECT_EQ(a->messages, 2u);
  EXPECT_EQ(a->camera.width(), 240);
  EXPECT_EQ(a->camera.height(), 180);
  EXPECT_DOUBLE_EQ(a->camera.fx(), 199.1);
  EXPECT_DOUBLE_EQ(a->camera.fy(), 198.5);
  EXPECT_DOUBLE_EQ(a->camera.cx(), 121.2);
  EXPECT_DOUBLE_EQ(a->camera.cy(), 92.3);
  EXPECT_EQ(a->camera.distortionModel(), DistortionModel::kRadtan);
  EXPECT_EQ(a->camera.coefficients(), radtan);

  const std::vector<double> fisheye{0.1, -0.02, 0.003, -0.0004};
  const auto b = readRosbagCalibration(bagWith("equi.bag", {bag::cameraInfo(640, 480, "equidistant", fisheye, 300, 301, 320, 240)}));
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->camera.distortionModel(), DistortionModel::kEquidistant);
  EXPECT_EQ(b->camera.coefficients(), fisheye);
  // No coefficients (or all zero): an undistorted pinhole.
  const auto c = readRosbagCalibration(bagWith("none.bag", {bag::cameraInfo(346, 260, "plumb_bob", {0, 0, 0, 0, 0}, 250, 250, 173, 130)}));
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->camera.distortionModel(), DistortionModel::kNone);
  EXPECT_EQ(c->camera.width(), 346);
  // No CameraInfo topic.
  EXPECT_FALSE(readRosbagCalibration(dir.write("no.bag", bag::buildBag({kDvs}, {bag::Chunk{{events(0, 3)}}}))).has_value());
}

TEST(RosbagCalibration, BadCameraInfo) {
  TempDir dir;
  auto errorFor = [&](const std::string& name, const std::string& info) {
    const std::string path = dir.write(name, bag::buildBag({kInfo}, {bag::Chunk{{{4, kT0, info}}}}));
    return bagError([&] { readRosbagCalibration(path); });
  };
  EXPECT_NE(errorFor("model.bag", bag::cameraInfo(240, 180, "rational_polynomial", {0.1, 0, 0, 0, 0, 0, 0, 0}, 200, 200, 120, 90))
                .find("message 0 of topic /dvs/camera_info: distortion model 'rational_polynomial' is not read by "
                      "AsynEVO (plumb_bob, equidistant)"),
            std::string::npos);
  EXPECT_NE(errorFor("count.bag", bag::cameraInfo(240, 180, "equidistant", {0.1, 0.2}, 200, 200, 120, 90))
                .find("distortion model equidistant with 2 coefficients (k1..k4: 4)"),
            std::string::npos);
  EXPECT_NE(errorFor("uncal.bag", bag::cameraInfo(240, 180, "plumb_bob", {}, 0, 0, 0, 0)).find("uncalibrated"),
            std::string::npos);
  EXPECT_NE(errorFor("size.bag", bag::cameraInfo(0, 0, "plumb_bob", {}, 200, 200, 120, 90)).find("states a 0x0 image"),
            std::string::npos);
  std::string huge = bag::cameraInfo(240, 180, "plumb_bob", {0.1, 0.2, 0, 0, 0}, 200, 200, 120, 90);
  huge.replace(16 + 6 + 8 + 4 + 9, 4, bag::u32(0x40000000));  // D's count: 2^30 coefficients
  EXPECT_NE(errorFor("d.bag", huge).find("malformed message: D needs 8589934592 bytes"), std::string::npos)
      << errorFor("d.bag", huge);
  std::string cut = bag::cameraInfo(240, 180, "plumb_bob", {}, 200, 200, 120, 90);
  cut.resize(cut.size() - 1);
  EXPECT_NE(errorFor("cut.bag", cut).find("malformed message: binning and roi needs 25 bytes"), std::string::npos)
      << errorFor("cut.bag", cut);
  // Two CameraInfo topics and no event topic to choose by: the error lists them
  // (tests/io/rosbag_camera_info_test.cpp: the choice).
  bag::Connection right = kInfo;
  right.id = 5;
  right.topic = "/right/camera_info";
  const std::string two = dir.write(
      "two.bag", bag::buildBag({kInfo, right}, {bag::Chunk{{{4, kT0, bag::cameraInfo(240, 180, "plumb_bob", {}, 1, 1, 1, 1)},
                                                            {5, kT0, bag::cameraInfo(240, 180, "plumb_bob", {}, 1, 1, 1, 1)}}}}));
  EXPECT_NE(bagError([&] { readRosbagCalibration(two); })
                .find("the bag has 2 camera info topics: /dvs/camera_info (sensor_msgs/CameraInfo, 1 messages), "
                      "/right/camera_info (sensor_msgs/CameraInfo, 1 messages); choose one with --camera-info-topic NAME, "
                      "or give the camera's calibration as a file"),
            std::string::npos)
      << bagError([&] { readRosbagCalibration(two); });
  EXPECT_EQ(rosbagCameraInfoTopics(two).size(), 2u);
  bag::Connection other = kInfo;
  other.md5 = "1b5cf7f984c229b6141ceb3a955aa18f";
  const std::string md5 = dir.write("md5.bag", bag::buildBag({other}, {bag::Chunk{{{4, kT0, cut}}}}));
  EXPECT_NE(bagError([&] { readRosbagCalibration(md5); }).find("AsynEVO reads the revision with MD5 sum c9a58c1b0b154e0e6da7578cb991d214"),
            std::string::npos);
}

TEST(RosbagGroundTruth, DatasetPrecedence) {
  TempDir dir;
  std::vector<bag::Message> m{events(0, 5)};
  for (const bag::Message& p : poseMessages(1, bag::poseStamped, 4)) m.push_back(p);
  const std::string path = dir.write("rec.bag", bag::buildBag({kDvs, kPose}, {bag::Chunk{m}}));
  // The bag alone: its pose topic.
  DatasetFiles files = resolveDataset(path);
  auto gt = loadDatasetGroundTruth(files);
  ASSERT_TRUE(gt.has_value());
  EXPECT_EQ(gt->source, path + " (topic /optitrack/pose)");
  EXPECT_EQ(gt->poses.size(), 4u);
  EXPECT_TRUE(gt->note.empty());
  // A groundtruth.txt beside it wins, and the note names the topic not used.
  dir.write("groundtruth.txt", "1600000000.0 0 0 0 0 0 0 1\n1600000000.1 1 0 0 0 0 0 1\n");
  files = resolveDataset(dir.path().string());
  gt = loadDatasetGroundTruth(files);
  ASSERT_TRUE(gt.has_value());
  EXPECT_EQ(gt->poses.size(), 2u);
  EXPECT_NE(gt->source.find("groundtruth.txt"), std::string::npos);
  EXPECT_NE(gt->note.find("the bag's pose topic(s) /optitrack/pose not used: the file beside the bag wins"),
            std::string::npos)
      << gt->note;
  // --gt-topic wins over the file.
  gt = loadDatasetGroundTruth(files, "/optitrack/pose");
  EXPECT_EQ(gt->poses.size(), 4u);
  EXPECT_NE(gt->note.find("is not used (--gt-topic given)"), std::string::npos);
  // --gt-topic with events that are not a bag.
  std::filesystem::create_directories(dir.path() / "ecd");
  dir.write("ecd/events.txt", "0.1 1 1 1\n");
  EXPECT_NE(bagError([&] { checkGroundTruthChoice(resolveDataset(dir.file("ecd")), "/pose"); })
                .find("--gt-topic '/pose' names a topic of a ROS bag, but the events file is not a ROS bag"),
            std::string::npos);
}

}  // namespace
}  // namespace asynevo
