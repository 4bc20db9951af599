#pragma once
// The --sensor WxH option of the commands that read events (info, run, track, convert): one definition,
// so every command checks and describes it alike. A malformed value is a usage error naming the flag.

#include <CLI/CLI.hpp>

#include <string>

#include "asynevo/io/sensor_size.hpp"

namespace asynevo::cli {

inline CLI::Option* addSensorOption(CLI::App* cmd, std::string& value) {
  const CLI::Validator size_check(
      [](std::string& text) {
        return tryParseSensorSize(text) ? std::string() : "'" + text + "' is not WxH, " + kSensorSizeSyntax;
      },
      "WxH");
  return cmd
      ->add_option("--sensor", value,
                   "sensor size WxH in pixels, e.g. 346x260; overrides the configuration's sensor block, a "
                   "sensor.yaml in the folder, the calibration's resolution and the format's default (a size "
                   "the file's header states must agree)")
      ->check(size_check);
}

/// The --topic NAME option of the same commands: which event topic of a ROS bag to read (needed only when
/// the bag has more than one).
inline CLI::Option* addTopicOption(CLI::App* cmd, std::string& value) {
  return cmd->add_option("--topic", value,
                         "ROS bag: the event topic to read (dvs_msgs/EventArray or event_camera_msgs/EventPacket); "
                         "needed only when the bag has several");
}

/// The --rectify-map FILE|none option of the same commands: DSEC's rectification map
/// (docs/reference/formats.md#rectification).
inline CLI::Option* addRectifyMapOption(CLI::App* cmd, std::string& value) {
  return cmd->add_option(
      "--rectify-map", value,
      "DSEC: the rectification map (rectify_map.h5) to apply to the events, which are then in the "
      "rectified camera's pixels (calibration: DSEC's camRect0 or camRect3, no distortion); default: the "
      "rectify_map.h5 beside the events file, if any; 'none' reads raw pixels");
}

/// The --camera-info-topic NAME option of the commands that read a calibration (info, run): which
/// sensor_msgs/CameraInfo topic of a ROS bag is the camera (docs/reference/formats_rosbag.md#calibration).
inline CLI::Option* addCameraInfoTopicOption(CLI::App* cmd, std::string& value) {
  return cmd->add_option("--camera-info-topic", value,
                         "ROS bag: the sensor_msgs/CameraInfo topic that is the calibration; needed only when the "
                         "bag has several and none is in the event topic's namespace (/dvs/events -> "
                         "/dvs/camera_info); when given it wins over a calibration file beside the bag");
}

/// The --gt-topic NAME option of the commands that read ground truth (info, run, eval): which pose topic of a
/// ROS bag is the ground truth (docs/reference/formats_rosbag.md#ground-truth).
inline CLI::Option* addGtTopicOption(CLI::App* cmd, std::string& value) {
  return cmd->add_option("--gt-topic", value,
                         "ROS bag: the pose topic that is the ground truth (geometry_msgs/PoseStamped, "
                         "geometry_msgs/TransformStamped or nav_msgs/Odometry), or TOPIC:FRAME for the child frame FRAME "
                         "of a tf2_msgs/TFMessage topic such as /tf; needed only when the bag has several; when given "
                         "it wins over a groundtruth.txt beside the bag");
}

}  // namespace asynevo::cli
