#pragma once
// The node's private parameters (~name), read once at start-up. Table: docs/guide/ros.md#parameters.

#include <ros/node_handle.h>

#include <string>

namespace asynevo::ros_node {

struct NodeOptions {
  std::string config;  ///< YAML configuration, as `asynevo run --config` ("" = the defaults)
  std::string calib;   ///< calibration file (ECD calib.txt or Kalibr camchain), as `--calib`
  std::string sensor;  ///< "WxH" for an ECD calib.txt (else the config's sensor block, else 240x180)
  bool use_camera_info =
      false;  ///< take the calibration from the first sensor_msgs/CameraInfo on camera_info
  std::string backend = "window";
  bool realtime = false;  ///< the estimator's wall-time cap of `asynevo run --realtime` (non-deterministic)
  std::string world_frame = "world";
  std::string camera_frame = "camera";
  bool publish_tf = true;
  int max_queue_events = 5000000;  ///< events waiting for the estimator; a message beyond is dropped, counted
  double stats_period_s = 1.0;     ///< period of the log line and the ~stats message (0: none)
  int subscriber_queue = 1000;     ///< roscpp queue of the events subscription (messages)
};

/// Reads the parameters from the node's private handle. Throws asynevo::ConfigError naming the parameter for
/// a value out of range (a negative queue, an unknown backend, both or neither calibration source, ...).
NodeOptions readNodeOptions(const ros::NodeHandle& private_nh);

}  // namespace asynevo::ros_node
