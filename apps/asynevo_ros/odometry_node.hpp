#pragma once
// The ROS node: dvs_msgs/EventArray in, poses out. The subscription callback (roscpp's spinner thread)
// checks each message (event_array_check.hpp) and queues its events in a LiveEventReader; a worker thread
// runs the two-thread pipeline of `asynevo run` (pipeline::Pipeline, offline mode: the same frontend,
// estimator and call order, so the same events give the same trajectory) on that reader, paced by the
// messages' arrival. In the estimator's thread, the node publishes the newest knot of the sliding window
// whenever a knot was added (~odometry, ~pose, TF) and every knot once it is final (~pose_final).
// Lag (a message's arrival to the estimator having processed its events) is logged every stats_period and
// published with the counters on ~stats. docs/guide/ros.md.

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/config/config.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/pipeline/pipeline.hpp"
#include "dvs_msgs/EventArray.h"
#include "event_array_check.hpp"
#include "live_event_reader.hpp"
#include "node_options.hpp"

namespace asynevo::ros_node {

class OdometryNode {
 public:
  /// Loads the configuration and, unless use_camera_info, the calibration (ConfigError / InputError on
  /// failure), then subscribes and starts the pipeline.
  OdometryNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options);
  ~OdometryNode();
  OdometryNode(const OdometryNode&) = delete;
  OdometryNode& operator=(const OdometryNode&) = delete;

  /// End of the stream: stops taking messages, processes the queue, makes the estimator's last solve,
  /// publishes the remaining final knots and logs the summary. Called once before ros::shutdown().
  void finish();

 private:
  class Output;  // the pipeline's output: publishes, in the estimator's thread

  /// What the pipeline reports, for the log line and ~stats (guarded by mutex_).
  struct Progress {
    uint64_t events_processed = 0;  ///< by the frontend
    double backend_behind_s = 0;    ///< event time the estimator is behind the frontend
    uint64_t knots_published = 0;
    uint64_t final_knots_published = 0;
    double lag_s = 0;  ///< the newest message done: its arrival to the estimator passing its events
    double max_lag_period_s = 0;  ///< the largest since the last log line
    double max_lag_s = 0;         ///< the largest since start
  };

  void startPipeline(const CameraModel& camera, const std::string& origin);
  void onEvents(const dvs_msgs::EventArray::ConstPtr& msg);
  void onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& msg);
  void onStatsTimer(const ros::WallTimerEvent& event);
  void run();
  void publishNewest(const backend::Knot& knot);
  void publishFinal(const std::vector<backend::Knot>& knots);
  void markerDone(int64_t t_ns);
  std::string statsJson();

  NodeOptions options_;
  Config config_;
  ros::Subscriber events_sub_, camera_info_sub_;
  ros::Publisher odometry_pub_, pose_pub_, pose_final_pub_, tf_pub_, stats_pub_;
  ros::WallTimer stats_timer_;

  // Set once by startPipeline (under mutex_), then used by the pipeline's threads.
  std::unique_ptr<LiveEventReader> reader_;
  std::unique_ptr<frontend::Frontend> frontend_;
  std::unique_ptr<backend::Estimator> estimator_;
  std::unique_ptr<Output> output_;
  std::thread worker_;

  std::mutex mutex_;  // guards the members below
  bool stopping_ = false;
  bool failed_ = false;  // the pipeline stopped on an error
  StreamState stream_;
  uint64_t messages_received_ = 0, messages_accepted_ = 0, events_received_ = 0;
  uint64_t before_calibration_ = 0, dropped_overload_ = 0, dropped_overload_events_ = 0, dropped_failed_ = 0;
  uint64_t camera_info_rejected_ = 0;
  uint64_t clamped_times_ = 0;    // events set to their predecessor's time (input.max_time_reversal_us)
  uint64_t logged_messages_ = 0;  // messages_received_ at the last log line
  SkipCounters skipped_{};
  Progress progress_;
  bool initialized_ = false;
  uint64_t features_ = 0;
  pipeline::PipelineStats pipeline_stats_;  // after finish()
};

}  // namespace asynevo::ros_node
