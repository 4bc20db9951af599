#pragma once
// The ROS node: dvs_msgs/EventArray in, poses out. The subscription callback (roscpp's spinner thread)
// checks each message (event_array_check.hpp) and queues its events; a worker thread feeds them to
// pipeline::EventFeed (the streaming API of asynevo.Stream: the frontend and the estimator of
// `asynevo run`, in its call order) as they arrive, and publishes the newest knot of the sliding window
// whenever a knot is added (~odometry, ~pose, TF) and every knot once it is final (~pose_final).
// Backend lag (arrival of a message to the end of its processing) is logged every stats_period and
// published with the counters on ~stats. docs/guide/ros.md.

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/pipeline/event_feed.hpp"
#include "dvs_msgs/EventArray.h"
#include "event_array_check.hpp"
#include "node_options.hpp"

namespace asynevo::ros_node {

class OdometryNode {
 public:
  /// Loads the configuration and, unless use_camera_info, the calibration (ConfigError / InputError on
  /// failure), then subscribes and starts the worker.
  OdometryNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options);
  ~OdometryNode();
  OdometryNode(const OdometryNode&) = delete;
  OdometryNode& operator=(const OdometryNode&) = delete;

  /// End of the stream: stops taking messages, processes the queue, makes the estimator's last solve,
  /// publishes the remaining final knots and logs the summary. Called once before ros::shutdown().
  void finish();

 private:
  struct Batch {
    std::vector<Event> events;
    std::chrono::steady_clock::time_point arrived;
  };
  /// What the worker reports, for the log line and ~stats (guarded by mutex_).
  struct Progress {
    uint64_t events_processed = 0;
    int64_t last_processed_t_ns = 0;
    uint64_t knots_published = 0;
    uint64_t final_knots_published = 0;
    double lag_s = 0;             ///< the last processed message's arrival to the end of its processing
    double max_lag_period_s = 0;  ///< the largest since the last log line
    double max_lag_s = 0;         ///< the largest since start
    bool initialized = false;
    uint64_t features = 0;
    uint64_t frontend_dropped = 0;
  };

  void startFeed(const CameraModel& camera, const std::string& origin);
  void onEvents(const dvs_msgs::EventArray::ConstPtr& msg);
  void onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& msg);
  void onStatsTimer(const ros::WallTimerEvent& event);
  void work();
  void process(const Batch& batch);
  void publishNewKnots();
  void logSummary();
  std::string statsJson();

  NodeOptions options_;
  Config config_;
  ros::Subscriber events_sub_, camera_info_sub_;
  ros::Publisher odometry_pub_, pose_pub_, pose_final_pub_, tf_pub_, stats_pub_;
  ros::WallTimer stats_timer_;

  std::mutex mutex_;  // guards everything below it up to the worker-only members
  std::condition_variable wake_;
  std::deque<Batch> queue_;
  uint64_t queued_events_ = 0;
  bool stopping_ = false;
  std::unique_ptr<pipeline::EventFeed> feed_;  // created once the calibration is known
  std::string calibration_origin_;
  StreamState stream_;
  uint64_t messages_received_ = 0, messages_accepted_ = 0, events_received_ = 0;
  uint64_t before_calibration_ = 0, dropped_overload_ = 0, dropped_overload_events_ = 0;
  uint64_t camera_info_rejected_ = 0;
  uint64_t logged_messages_ = 0;  // messages_received_ at the last log line
  SkipCounters skipped_{};
  Progress progress_;

  // Worker thread only.
  int64_t newest_published_t_ns_ = -1;
  std::thread worker_;
};

}  // namespace asynevo::ros_node
