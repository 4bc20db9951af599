#include "odometry_node.hpp"

#include <fmt/format.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include "asynevo/backend/sliding_window_estimator.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/camera_info.hpp"
#include "asynevo/io/sensor_size.hpp"
#include "asynevo/pipeline/run.hpp"
#include "pose_messages.hpp"

namespace asynevo::ros_node {

/// Runs in the estimator's thread, in the pipeline's order: before each time marker the estimator's state
/// is that after the previous one, so its newest knot can be read without a lock.
class OdometryNode::Output final : public pipeline::PipelineOutput {
 public:
  Output(OdometryNode& node, const backend::Estimator& estimator)
      : node_(node), window_(dynamic_cast<const backend::SlidingWindowEstimator*>(&estimator)) {}

  void onMarker(int64_t t_ns) override {
    node_.markerDone(t_ns);
    if (window_ == nullptr || !window_->tracking() || window_->trajectory().empty()) return;
    const backend::Knot& newest = window_->trajectory().knots().rbegin()->second;
    if (newest.t_ns <= newest_published_t_ns_) return;
    newest_published_t_ns_ = newest.t_ns;
    node_.publishNewest(newest);
  }
  void onFinalKnots(const std::vector<backend::Knot>& knots) override { node_.publishFinal(knots); }

 private:
  OdometryNode& node_;
  const backend::SlidingWindowEstimator* window_;  // nullptr for the full-history baselines
  int64_t newest_published_t_ns_ = -1;
};

namespace {

double secondsSince(LiveEventReader::Clock::time_point t) {
  return std::chrono::duration<double>(LiveEventReader::Clock::now() - t).count();
}

}  // namespace

OdometryNode::OdometryNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options)
    : options_(std::move(options)) {
  config_ = options_.config.empty() ? Config() : loadConfig(options_.config);
  odometry_pub_ = private_nh.advertise<nav_msgs::Odometry>("odometry", 100);
  pose_pub_ = private_nh.advertise<geometry_msgs::PoseStamped>("pose", 100);
  pose_final_pub_ = private_nh.advertise<geometry_msgs::PoseStamped>("pose_final", 1000);
  stats_pub_ = private_nh.advertise<std_msgs::String>("stats", 10, true);
  if (options_.publish_tf) tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  if (!options_.use_camera_info) {
    int w = config_.sensor.width, h = config_.sensor.height;
    if (!options_.sensor.empty()) {
      const SensorSize size = parseSensorSize(options_.sensor, private_nh.getNamespace() + "/sensor");
      w = size.width;
      h = size.height;
    }
    startPipeline(readCalibration(options_.calib, w, h), options_.calib);
  } else {
    camera_info_sub_ = nh.subscribe("camera_info", 10, &OdometryNode::onCameraInfo, this);
    ROS_INFO("asynevo: waiting for the calibration on %s", camera_info_sub_.getTopic().c_str());
  }
  events_sub_ = nh.subscribe("events", static_cast<uint32_t>(options_.subscriber_queue),
                             &OdometryNode::onEvents, this, ros::TransportHints().tcpNoDelay());
  if (options_.stats_period_s > 0)
    stats_timer_ =
        nh.createWallTimer(ros::WallDuration(options_.stats_period_s), &OdometryNode::onStatsTimer, this);
  const std::string tf =
      options_.publish_tf ? fmt::format(", TF {} -> {}", options_.world_frame, options_.camera_frame) : "";
  ROS_INFO("asynevo: events from %s, poses on %s, %s and %s%s", events_sub_.getTopic().c_str(),
           odometry_pub_.getTopic().c_str(), pose_pub_.getTopic().c_str(), pose_final_pub_.getTopic().c_str(),
           tf.c_str());
}

OdometryNode::~OdometryNode() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  if (reader_) reader_->close();
  if (worker_.joinable()) worker_.join();
}

void OdometryNode::startPipeline(const CameraModel& camera, const std::string& origin) {
  if (config_.sensor.set_by_file &&
      (config_.sensor.width != camera.width() || config_.sensor.height != camera.height()))
    throw ConfigError(fmt::format(
        "the configuration {} sets a {}x{} sensor but the calibration from {} is {}x{}", options_.config,
        config_.sensor.width, config_.sensor.height, origin, camera.width(), camera.height()));
  Config config = config_;
  config.sensor.width = camera.width();
  config.sensor.height = camera.height();
  config.validate();
  config.validateForSensor();
  auto fe = std::make_unique<frontend::Frontend>(config.frontend, camera.width(), camera.height(),
                                                 camera.undistortionTable<float>());
  auto estimator = pipeline::makeEstimator(*pipeline::parseBackendKind(options_.backend), config, camera, *fe,
                                           options_.realtime);
  std::lock_guard<std::mutex> lock(mutex_);
  if (stopping_ || reader_) return;
  reader_ = std::make_unique<LiveEventReader>(camera.width(), camera.height(),
                                              static_cast<uint64_t>(options_.max_queue_events));
  frontend_ = std::move(fe);
  estimator_ = std::move(estimator);
  output_ = std::make_unique<Output>(*this, *estimator_);
  stream_.width = camera.width();
  stream_.height = camera.height();
  stream_.max_time_reversal_ns = std::llround(config.input.max_time_reversal_us * 1e3);
  worker_ = std::thread([this] { run(); });
  ROS_INFO("asynevo: %dx%d camera from %s, fx %.2f fy %.2f cx %.2f cy %.2f, estimator %s", camera.width(),
           camera.height(), origin.c_str(), camera.fx(), camera.fy(), camera.cx(), camera.cy(),
           estimator_->name());
}

void OdometryNode::run() {
  try {
    pipeline::Pipeline pipe(*reader_, *frontend_, *estimator_, *output_, pipeline::PipelineOptions{});
    const pipeline::PipelineStats stats = pipe.run([this](const pipeline::PipelineProgress& p) {
      std::lock_guard<std::mutex> lock(mutex_);
      progress_.events_processed = p.events;
      progress_.backend_behind_s = static_cast<double>(p.lag_ns) * 1e-9;
      features_ = frontend_->stats().features_created;
    });
    std::lock_guard<std::mutex> lock(mutex_);
    pipeline_stats_ = stats;
  } catch (const std::exception& e) {  // the node stays up (and says so) rather than dying with the stream
    ROS_ERROR("asynevo: the pipeline stopped: %s; further event messages are dropped", e.what());
    reader_->close();
    std::lock_guard<std::mutex> lock(mutex_);
    failed_ = true;
  }
}

void OdometryNode::onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& msg) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (reader_ || stopping_) return;
  }
  CameraInfoFields info;
  info.width = msg->width;
  info.height = msg->height;
  info.distortion_model = msg->distortion_model;
  info.d = msg->D;
  std::copy(msg->K.begin(), msg->K.end(), info.k.begin());
  try {
    startPipeline(cameraFromCameraInfo(info), "the camera_info topic " + camera_info_sub_.getTopic());
    camera_info_sub_.shutdown();
  } catch (const Error& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++camera_info_rejected_;
    ROS_WARN_THROTTLE(5.0, "asynevo: camera info rejected (%llu so far): %s",
                      static_cast<unsigned long long>(camera_info_rejected_), e.what());
  }
}

void OdometryNode::onEvents(const dvs_msgs::EventArray::ConstPtr& msg) {
  const auto arrived = LiveEventReader::Clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  ++messages_received_;
  events_received_ += msg->events.size();
  if (stopping_) return;
  if (!reader_) {
    if (++before_calibration_ == 1)
      ROS_WARN("asynevo: event messages arrive before the calibration (camera_info): skipped until it comes");
    return;
  }
  if (failed_) {
    ++dropped_failed_;
    return;
  }
  const StreamState state = stream_;
  lock.unlock();  // the check and the conversion run without the lock
  CheckResult r = checkEventArray(*msg, state);
  lock.lock();
  if (r.reason != SkipReason::kNone) {
    const uint64_t n = ++skipped_[static_cast<std::size_t>(r.reason)];
    const char* name = skipReasonName(r.reason);
    if (n == 1) {
      ROS_WARN("asynevo: skipped message %u from %s (%s): %s", msg->header.seq,
               msg->header.frame_id.empty() ? "?" : msg->header.frame_id.c_str(), name, r.message.c_str());
    } else {
      ROS_WARN_THROTTLE(5.0, "asynevo: skipped message (%s, %llu so far): %s", name,
                        static_cast<unsigned long long>(n), r.message.c_str());
    }
    return;
  }
  const std::size_t count = r.events.size();
  const uint64_t clamped = r.clamped;
  const int64_t last_t = r.events.back().t_ns;
  if (!reader_->push(std::move(r.events), arrived)) {
    ++dropped_overload_;
    dropped_overload_events_ += count;
    ROS_WARN_THROTTLE(
        5.0,
        "asynevo: the pipeline is behind by %llu queued events (max_queue_events %d): dropped a "
        "message of %zu events (%llu messages so far)",
        static_cast<unsigned long long>(reader_->queuedEvents()), options_.max_queue_events, count,
        static_cast<unsigned long long>(dropped_overload_));
    return;
  }
  ++messages_accepted_;
  clamped_times_ += clamped;
  stream_.has_last = true;
  stream_.last_t_ns = last_t;
}

void OdometryNode::markerDone(int64_t t_ns) {
  const std::optional<LiveEventReader::Clock::time_point> arrived = reader_->doneBefore(t_ns);
  const bool initialized = estimator_->stats().initialized;
  std::lock_guard<std::mutex> lock(mutex_);
  initialized_ = initialized;
  if (!arrived) return;
  const double lag = secondsSince(*arrived);
  Progress& p = progress_;
  p.lag_s = lag;
  p.max_lag_period_s = std::max(p.max_lag_period_s, lag);
  p.max_lag_s = std::max(p.max_lag_s, lag);
}

void OdometryNode::publishNewest(const backend::Knot& knot) {
  if (!ros::ok()) return;  // shut down through ROS (rosnode kill): the publishers are gone
  odometry_pub_.publish(odometryMessage(knot, options_.world_frame, options_.camera_frame));
  pose_pub_.publish(poseMessage(knot, options_.world_frame));
  if (options_.publish_tf) {
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(transformMessage(knot, options_.world_frame, options_.camera_frame));
    tf_pub_.publish(tf);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++progress_.knots_published;
}

void OdometryNode::publishFinal(const std::vector<backend::Knot>& knots) {
  if (!ros::ok()) return;
  for (const backend::Knot& k : knots) pose_final_pub_.publish(poseMessage(k, options_.world_frame));
  std::lock_guard<std::mutex> lock(mutex_);
  progress_.final_knots_published += knots.size();
}

std::string OdometryNode::statsJson() {
  std::string skipped;
  uint64_t skipped_total = 0;
  for (std::size_t i = 1; i < kSkipReasons; ++i) {
    skipped += fmt::format("{}\"{}\": {}", i > 1 ? ", " : "", skipReasonName(static_cast<SkipReason>(i)),
                           skipped_[i]);
    skipped_total += skipped_[i];
  }
  const Progress& p = progress_;
  return fmt::format(
      "{{\"messages_received\": {}, \"messages_accepted\": {}, \"events_received\": {}, "
      "\"events_processed\": {}, "
      "\"queued_events\": {}, \"lag_s\": {:.6f}, \"max_lag_s\": {:.6f}, \"backend_behind_s\": {:.6f}, "
      "\"initialized\": {}, \"features\": {}, \"knots_published\": {}, \"final_knots_published\": {}, "
      "\"before_calibration\": {}, \"camera_info_rejected\": {}, \"dropped_overload\": {}, "
      "\"dropped_overload_events\": {}, \"dropped_after_failure\": {}, \"clamped_times\": {}, "
      "\"skipped_total\": {}, \"skipped\": {{{}}}}}",
      messages_received_, messages_accepted_, events_received_, p.events_processed,
      reader_ ? reader_->queuedEvents() : 0, p.lag_s, p.max_lag_s, p.backend_behind_s,
      initialized_ ? "true" : "false", features_, p.knots_published, p.final_knots_published,
      before_calibration_, camera_info_rejected_, dropped_overload_, dropped_overload_events_,
      dropped_failed_, clamped_times_, skipped_total, skipped);
}

void OdometryNode::onStatsTimer(const ros::WallTimerEvent&) {
  std_msgs::String msg;
  std::lock_guard<std::mutex> lock(mutex_);
  msg.data = statsJson();
  stats_pub_.publish(msg);
  const uint64_t queued = reader_ ? reader_->queuedEvents() : 0;
  // A line while messages arrive or wait; none while the stream is idle.
  if (messages_received_ == logged_messages_ && queued == 0) return;
  logged_messages_ = messages_received_;
  uint64_t skipped_total = 0;
  for (uint64_t n : skipped_) skipped_total += n;
  Progress& p = progress_;
  ROS_INFO(
      "asynevo: %llu events processed, %llu queued; lag %.3f s (max %.3f s in the last %.1f s), estimator "
      "%.3f s of event time behind; %s, %llu knots; %llu messages skipped, %llu dropped (overload)",
      static_cast<unsigned long long>(p.events_processed), static_cast<unsigned long long>(queued), p.lag_s,
      p.max_lag_period_s, options_.stats_period_s, p.backend_behind_s,
      initialized_ ? "initialized" : "initializing", static_cast<unsigned long long>(p.knots_published),
      static_cast<unsigned long long>(skipped_total), static_cast<unsigned long long>(dropped_overload_));
  p.max_lag_period_s = 0;
}

void OdometryNode::finish() {
  events_sub_.shutdown();
  camera_info_sub_.shutdown();
  stats_timer_.stop();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  if (reader_) reader_->close();           // the pipeline processes what is queued, then finishes
  if (worker_.joinable()) worker_.join();  // the estimator's last solve and final knots are published
  std_msgs::String msg;
  std::lock_guard<std::mutex> lock(mutex_);
  msg.data = statsJson();
  if (ros::ok()) stats_pub_.publish(msg);
  std::string summary = "asynevo: finished: " + msg.data;
  if (pipeline_stats_.events > 0)
    summary += fmt::format(
        "\nasynevo: pipeline: {} events over {:.3f} s of event time; the estimator was busy {:.2f} s and at "
        "most "
        "{:.3f} s of event time behind the frontend",
        pipeline_stats_.events, pipeline_stats_.spanSeconds(), pipeline_stats_.backend_busy_seconds,
        static_cast<double>(pipeline_stats_.max_lag_ns) * 1e-9);
  if (ros::ok()) {
    ROS_INFO("%s", summary.c_str());
  } else {  // after a shutdown through ROS, rosconsole is shut down too
    std::fprintf(stderr, "%s\n", summary.c_str());
  }
}

}  // namespace asynevo::ros_node
