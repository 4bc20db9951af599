#pragma once
// Ground truth and calibration stored in a ROS1 bag beside its events (docs/reference/formats_rosbag.md):
// poses from one topic of geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry
// (or one child frame of a tf2_msgs/TFMessage topic),
// the camera from the first message of a sensor_msgs/CameraInfo topic. Messages are decoded from their
// ROS1 serialization by hand (no ROS library), every length checked; a malformed message is an InputError
// naming the bag, the byte offset and the message's index among its topic's messages.

#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/stamped_pose.hpp"

namespace asynevo {

/// True when the file starts with the magic of a ROS1 bag ("#ROSBAG V").
bool isRosbag(const std::string& path);

/// The option that names a bag's pose topic, in messages.
inline constexpr const char* kGroundTruthTopicFlag = "--gt-topic";
/// The option that names a bag's CameraInfo topic, in messages.
inline constexpr const char* kCameraInfoTopicFlag = "--camera-info-topic";

struct BagGroundTruth {
  StampedTrajectory poses;  ///< T_w_c per message, stamped with the header's stamp (ROS time)
  std::string topic;
  std::string type;
};

/// The poses of the bag's pose topic: `topic` when given (an error when it is missing or not a pose type),
/// else the bag's only topic of a pose type; std::nullopt when there is none. `topic` may also be
/// "NAME:FRAME" or "NAME" for a tf2_msgs/TFMessage topic: the transforms to child frame FRAME (or to the
/// topic's only child frame), and the result's topic is then "NAME:FRAME"; tf topics are read only when
/// named. Several pose topics and no
/// `topic` is an InputError listing them. Poses must be finite, quaternions non-zero (normalized), stamps
/// non-decreasing.
std::optional<BagGroundTruth> readRosbagGroundTruth(const std::string& path, const std::string& topic = "");

/// What readRosbagGroundTruth checks before decoding a message (the index only): the named topic exists,
/// is of a pose type and of the known revision, or without a name there is at most one pose topic.
void checkRosbagPoseTopic(const std::string& path, const std::string& topic = "");

/// The bag's topics of a pose type (the index only; nothing is decoded).
std::vector<std::string> rosbagPoseTopics(const std::string& path);

/// The bag's sensor_msgs/CameraInfo topics (the index only).
std::vector<std::string> rosbagCameraInfoTopics(const std::string& path);

struct BagCalibration {
  CameraModel camera;
  std::string topic;
  uint64_t messages = 0;  ///< messages of the topic (only the first is used)
  std::string note;       ///< how the topic was chosen among several ("" = named, or the only one)
};

/// The camera of a sensor_msgs/CameraInfo topic of the bag (its first message):
///   1. `topic` (--camera-info-topic) when given: an InputError when the bag lacks it, it is of another type
///      or revision, or it has no message;
///   2. else the bag's only CameraInfo topic;
///   3. else, among several, the only one in the namespace of the event topic (`event_topic`, or the bag's only
///      event topic when ""): /dvs/events -> /dvs/camera_info. Still several (or none there): an InputError
///      listing them.
/// std::nullopt when the bag has no CameraInfo topic (and none is named) or its topic has no message.
std::optional<BagCalibration> readRosbagCalibration(const std::string& path, const std::string& topic = "",
                                                    const std::string& event_topic = "");

/// The header stamp (ROS time, ns) of the first message of an event_camera_msgs/EventPacket topic, whose
/// events carry the camera's clock instead; std::nullopt when `topic` is not such a topic or has no message.
std::optional<int64_t> rosbagFirstPacketStamp(const std::string& path, const std::string& topic);

/// "FILE (topic NAME)": how a bag's topic is named as a source in summaries and messages.
std::string bagTopicSource(const std::string& path, const std::string& topic);

}  // namespace asynevo
