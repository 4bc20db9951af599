// Choosing among several sensor_msgs/CameraInfo topics of a ROS1 bag (bags built byte by byte from the
// specification, rosbag_fixture.hpp): a named topic, the one in the event topic's namespace, the error that
// lists them; and the calibration precedence of io/dataset.hpp chooseDatasetCalibration.
#include <gtest/gtest.h>

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

bag::Connection eventTopic(uint32_t id, const std::string& name) {
  return {id, name, bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
}
bag::Connection infoTopic(uint32_t id, const std::string& name) {
  return {id, name, bag::kCameraInfoType, bag::kCameraInfoMd5, "(definition)"};
}

bag::Message events(uint32_t connection) {
  std::vector<bag::DvsEvent> e;
  for (int i = 0; i < 4; ++i) e.push_back({static_cast<uint16_t>(i), static_cast<uint16_t>(i), kT0 + uint64_t(i) * 1000, true});
  return {connection, kT0, bag::eventArray(240, 180, e)};
}

/// A CameraInfo whose fx tells the topics apart.
bag::Message info(uint32_t connection, double fx) {
  return {connection, kT0, bag::cameraInfo(240, 180, "plumb_bob", {}, fx, fx, 120, 90)};
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A stereo bag: /davis/left/{events,camera_info}, /davis/right/{events,camera_info}.
std::string stereoBag(const TempDir& dir) {
  return dir.write("stereo.bag", bag::buildBag({eventTopic(0, "/davis/left/events"), infoTopic(1, "/davis/left/camera_info"),
                                                eventTopic(2, "/davis/right/events"), infoTopic(3, "/davis/right/camera_info")},
                                               {bag::Chunk{{events(0), info(1, 201), events(2), info(3, 203)}}}));
}

TEST(RosbagCameraInfo, TheEventTopicsNamespaceChoosesAmongSeveral) {
  TempDir dir;
  const std::string stereo = stereoBag(dir);
  const auto left = readRosbagCalibration(stereo, "", "/davis/left/events");
  ASSERT_TRUE(left.has_value());
  EXPECT_EQ(left->topic, "/davis/left/camera_info");
  EXPECT_DOUBLE_EQ(left->camera.fx(), 201);
  EXPECT_EQ(left->note, "chosen among 2 CameraInfo topics as the one in the namespace /davis/left of the event topic "
                        "/davis/left/events (--camera-info-topic NAME chooses another)");
  const auto right = readRosbagCalibration(stereo, "", "/davis/right/events");
  ASSERT_TRUE(right.has_value());
  EXPECT_EQ(right->topic, "/davis/right/camera_info");
  EXPECT_DOUBLE_EQ(right->camera.fx(), 203);
  // A named topic wins over the namespace rule, and has no note.
  const auto named = readRosbagCalibration(stereo, "/davis/right/camera_info", "/davis/left/events");
  ASSERT_TRUE(named.has_value());
  EXPECT_EQ(named->topic, "/davis/right/camera_info");
  EXPECT_EQ(named->note, "");
  // Without --topic the stereo bag has no single event topic: the error lists the CameraInfo topics.
  EXPECT_NE(errorOf([&] { readRosbagCalibration(stereo); })
                .find(": the bag has 2 camera info topics: /davis/left/camera_info (sensor_msgs/CameraInfo, 1 "
                      "messages), /davis/right/camera_info (sensor_msgs/CameraInfo, 1 messages); choose one with "
                      "--camera-info-topic NAME, or give the camera's calibration as a file (--calib FILE, or "
                      "calib.txt or a camchain beside the bag)"),
            std::string::npos)
      << errorOf([&] { readRosbagCalibration(stereo); });

  // The bag's only event topic counts as the event topic: /dvs/events -> /dvs/camera_info.
  const std::string mono = dir.write(
      "mono.bag", bag::buildBag({eventTopic(0, "/dvs/events"), infoTopic(1, "/dvs/camera_info"), infoTopic(2, "/rgb/camera_info")},
                                {bag::Chunk{{events(0), info(1, 201), info(2, 500)}}}));
  const auto dvs = readRosbagCalibration(mono);
  ASSERT_TRUE(dvs.has_value());
  EXPECT_EQ(dvs->topic, "/dvs/camera_info");
  EXPECT_DOUBLE_EQ(dvs->camera.fx(), 201);
}

TEST(RosbagCameraInfo, StillAmbiguousOrWrongNamesAreErrors) {
  TempDir dir;
  // None in the event topic's namespace.
  const std::string none = dir.write(
      "none.bag", bag::buildBag({eventTopic(0, "/dvs/events"), infoTopic(1, "/left/camera_info"), infoTopic(2, "/right/camera_info")},
                                {bag::Chunk{{events(0), info(1, 201), info(2, 203)}}}));
  EXPECT_NE(errorOf([&] { readRosbagCalibration(none); })
                .find(": the bag has 2 camera info topics: /left/camera_info (sensor_msgs/CameraInfo, 1 messages), "
                      "/right/camera_info (sensor_msgs/CameraInfo, 1 messages); none is in the namespace /dvs of the "
                      "event topic /dvs/events; choose one with --camera-info-topic NAME"),
            std::string::npos)
      << errorOf([&] { readRosbagCalibration(none); });
  // Two in it.
  const std::string two = dir.write(
      "two.bag", bag::buildBag({eventTopic(0, "/dvs/events"), infoTopic(1, "/dvs/camera_info"), infoTopic(2, "/dvs/camera_info_rect")},
                               {bag::Chunk{{events(0), info(1, 201), info(2, 203)}}}));
  EXPECT_NE(errorOf([&] { readRosbagCalibration(two); })
                .find("; 2 are in the namespace /dvs of the event topic /dvs/events; choose one with --camera-info-topic "
                      "NAME"),
            std::string::npos)
      << errorOf([&] { readRosbagCalibration(two); });
  EXPECT_EQ(readRosbagCalibration(two, "/dvs/camera_info_rect")->topic, "/dvs/camera_info_rect");
  // Topics at the root: the namespace is "/".
  const std::string root = dir.write(
      "root.bag", bag::buildBag({eventTopic(0, "/events"), infoTopic(1, "/camera_info"), infoTopic(2, "/rgb/camera_info")},
                                {bag::Chunk{{events(0), info(1, 201), info(2, 203)}}}));
  EXPECT_EQ(readRosbagCalibration(root)->topic, "/camera_info");
  // A named topic that is missing, of another type, or without messages.
  EXPECT_NE(errorOf([&] { readRosbagCalibration(two, "/nope"); })
                .find("the bag has no topic '/nope' (--camera-info-topic); its topics: /dvs/events"),
            std::string::npos)
      << errorOf([&] { readRosbagCalibration(two, "/nope"); });
  EXPECT_NE(errorOf([&] { readRosbagCalibration(two, "/dvs/events"); })
                .find("topic /dvs/events (--camera-info-topic) holds dvs_msgs/EventArray messages, not a camera info "
                      "type AsynEVO reads (sensor_msgs/CameraInfo)"),
            std::string::npos)
      << errorOf([&] { readRosbagCalibration(two, "/dvs/events"); });
  const std::string empty = dir.write(
      "empty.bag", bag::buildBag({eventTopic(0, "/dvs/events"), infoTopic(1, "/dvs/camera_info")}, {bag::Chunk{{events(0)}}}));
  EXPECT_EQ(errorOf([&] { readRosbagCalibration(empty, "/dvs/camera_info"); }),
            empty + ": the camera info topic /dvs/camera_info (--camera-info-topic) has no messages");
  EXPECT_FALSE(readRosbagCalibration(empty).has_value());  // not named: no calibration from it
}

TEST(RosbagCameraInfo, DatasetCalibrationPrecedence) {
  TempDir dir;
  const std::string stereo = stereoBag(dir);
  DatasetFiles files = resolveDataset(stereo);
  // The bag alone, event topic /davis/right/events (--topic): its namespace's CameraInfo.
  DatasetCalibration c = chooseDatasetCalibration(files, "", "", "/davis/right/events");
  ASSERT_TRUE(c.bag.has_value());
  EXPECT_EQ(c.bag->topic, "/davis/right/camera_info");
  EXPECT_EQ(c.file, "");
  EXPECT_NE(c.note.find("chosen among 2 CameraInfo topics"), std::string::npos) << c.note;
  // A calibration file beside the bag wins over the topics.
  const std::string calib = dir.write("calib.txt", "199 198 120 90 0 0 0 0 0\n");
  files = resolveDataset(dir.path().string());
  c = chooseDatasetCalibration(files, "", "", "/davis/right/events");
  EXPECT_EQ(c.file, calib);
  EXPECT_FALSE(c.bag.has_value());
  EXPECT_EQ(c.note, "the bag's sensor_msgs/CameraInfo topic(s) /davis/left/camera_info, /davis/right/camera_info not "
                    "used: the file wins (--camera-info-topic NAME reads the bag's)");
  // --camera-info-topic wins over the file beside the bag.
  c = chooseDatasetCalibration(files, "", "/davis/left/camera_info", "/davis/right/events");
  ASSERT_TRUE(c.bag.has_value());
  EXPECT_EQ(c.bag->topic, "/davis/left/camera_info");
  EXPECT_EQ(c.note, "the file " + calib + " is not used (--camera-info-topic given)");
  // --calib wins over everything; with --camera-info-topic too it is an error.
  c = chooseDatasetCalibration(files, "/some/calib.txt", "", "");
  EXPECT_EQ(c.file, "/some/calib.txt");
  EXPECT_EQ(errorOf([&] { chooseDatasetCalibration(files, "/some/calib.txt", "/davis/left/camera_info", ""); }),
            "--calib /some/calib.txt and --camera-info-topic /davis/left/camera_info both name the calibration: give "
            "one of them");
  // --camera-info-topic on events that are not a bag.
  const std::string text = dir.write("events.txt", "0.1 1 1 1\n");
  EXPECT_EQ(errorOf([&] { chooseDatasetCalibration(resolveDataset(text), "", "/dvs/camera_info", ""); }),
            text + ": --camera-info-topic '/dvs/camera_info' names a topic of a ROS bag, but the events file is not a "
                   "ROS bag");
}

}  // namespace
}  // namespace asynevo
