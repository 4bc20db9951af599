#include "node_options.hpp"

#include <fmt/format.h>

#include "asynevo/core/error.hpp"
#include "asynevo/pipeline/run.hpp"

namespace asynevo::ros_node {

NodeOptions readNodeOptions(const ros::NodeHandle& nh) {
  NodeOptions o;
  nh.param("config", o.config, o.config);
  nh.param("calib", o.calib, o.calib);
  nh.param("sensor", o.sensor, o.sensor);
  nh.param("use_camera_info", o.use_camera_info, o.use_camera_info);
  nh.param("backend", o.backend, o.backend);
  nh.param("realtime", o.realtime, o.realtime);
  nh.param("world_frame", o.world_frame, o.world_frame);
  nh.param("camera_frame", o.camera_frame, o.camera_frame);
  nh.param("publish_tf", o.publish_tf, o.publish_tf);
  nh.param("max_queue_events", o.max_queue_events, o.max_queue_events);
  nh.param("stats_period", o.stats_period_s, o.stats_period_s);
  nh.param("subscriber_queue", o.subscriber_queue, o.subscriber_queue);

  const std::string ns = nh.getNamespace();
  if (o.use_camera_info && !o.calib.empty())
    throw ConfigError(
        fmt::format("{}/calib and {}/use_camera_info are both set: choose one calibration source", ns, ns));
  if (!o.use_camera_info && o.calib.empty())
    throw ConfigError(
        fmt::format("no calibration: set {}/calib to a calib.txt or Kalibr camchain, or "
                    "{}/use_camera_info to true to read the camera_info topic",
                    ns, ns));
  if (!pipeline::parseBackendKind(o.backend))
    throw ConfigError(
        fmt::format("{}/backend '{}' is not window, incremental or incremental-frozen", ns, o.backend));
  if (o.max_queue_events <= 0)
    throw ConfigError(fmt::format("{}/max_queue_events is {}; it must be positive", ns, o.max_queue_events));
  if (o.subscriber_queue <= 0)
    throw ConfigError(fmt::format("{}/subscriber_queue is {}; it must be positive", ns, o.subscriber_queue));
  if (o.stats_period_s < 0)
    throw ConfigError(
        fmt::format("{}/stats_period is {}; it must be 0 (off) or positive", ns, o.stats_period_s));
  if (o.world_frame.empty() || o.camera_frame.empty() || o.world_frame == o.camera_frame)
    throw ConfigError(fmt::format("{}/world_frame '{}' and {}/camera_frame '{}' must be set and differ", ns,
                                  o.world_frame, ns, o.camera_frame));
  return o;
}

}  // namespace asynevo::ros_node
