#include "odometry_node.hpp"

#include <fmt/format.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <utility>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/camera_info.hpp"
#include "asynevo/io/sensor_size.hpp"
#include "pose_messages.hpp"

namespace asynevo::ros_node {

namespace {

constexpr int64_t kSliceNs = 1000000;  // the feed's marker period: a knot is added at most once per slice

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

OdometryNode::OdometryNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options)
    : options_(std::move(options)) {
  config_ = options_.config.empty() ? Config() : loadConfig(options_.config);
  if (!options_.use_camera_info) {
    int w = config_.sensor.width, h = config_.sensor.height;
    if (!options_.sensor.empty()) {
      const SensorSize size = parseSensorSize(options_.sensor, private_nh.getNamespace() + "/sensor");
      w = size.width;
      h = size.height;
    }
    startFeed(readCalibration(options_.calib, w, h), options_.calib);
  }
  odometry_pub_ = private_nh.advertise<nav_msgs::Odometry>("odometry", 100);
  pose_pub_ = private_nh.advertise<geometry_msgs::PoseStamped>("pose", 100);
  pose_final_pub_ = private_nh.advertise<geometry_msgs::PoseStamped>("pose_final", 1000);
  stats_pub_ = private_nh.advertise<std_msgs::String>("stats", 10, true);
  if (options_.publish_tf) tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  worker_ = std::thread([this] { work(); });
  if (options_.use_camera_info) {
    camera_info_sub_ = nh.subscribe("camera_info", 10, &OdometryNode::onCameraInfo, this);
    ROS_INFO("asynevo: waiting for the calibration on %s", camera_info_sub_.getTopic().c_str());
  }
  events_sub_ = nh.subscribe("events", static_cast<uint32_t>(options_.subscriber_queue), &OdometryNode::onEvents,
                             this, ros::TransportHints().tcpNoDelay());
  if (options_.stats_period_s > 0)
    stats_timer_ = nh.createWallTimer(ros::WallDuration(options_.stats_period_s), &OdometryNode::onStatsTimer, this);
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
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void OdometryNode::startFeed(const CameraModel& camera, const std::string& origin) {
  const std::optional<pipeline::BackendKind> kind = pipeline::parseBackendKind(options_.backend);
  auto feed = std::make_unique<pipeline::EventFeed>(config_, camera, *kind);
  std::lock_guard<std::mutex> lock(mutex_);
  feed_ = std::move(feed);
  calibration_origin_ = origin;
  stream_.width = camera.width();
  stream_.height = camera.height();
  ROS_INFO("asynevo: %dx%d camera from %s, fx %.2f fy %.2f cx %.2f cy %.2f, backend %s", camera.width(),
           camera.height(), origin.c_str(), camera.fx(), camera.fy(), camera.cx(), camera.cy(), feed_->backendName());
}

void OdometryNode::onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& msg) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (feed_) return;
  }
  CameraInfoFields info;
  info.width = msg->width;
  info.height = msg->height;
  info.distortion_model = msg->distortion_model;
  info.d = msg->D;
  std::copy(msg->K.begin(), msg->K.end(), info.k.begin());
  try {
    startFeed(cameraFromCameraInfo(info), "the camera_info topic " + camera_info_sub_.getTopic());
    camera_info_sub_.shutdown();
  } catch (const Error& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++camera_info_rejected_;
    ROS_WARN_THROTTLE(5.0, "asynevo: camera info rejected (%llu so far): %s",
                      static_cast<unsigned long long>(camera_info_rejected_), e.what());
  }
}

void OdometryNode::onEvents(const dvs_msgs::EventArray::ConstPtr& msg) {
  const auto arrived = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  ++messages_received_;
  events_received_ += msg->events.size();
  if (stopping_) return;
  if (!feed_) {
    if (++before_calibration_ == 1)
      ROS_WARN("asynevo: event messages arrive before the calibration (camera_info): skipped until it comes");
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
  if (queued_events_ + r.events.size() > static_cast<uint64_t>(options_.max_queue_events)) {
    ++dropped_overload_;
    dropped_overload_events_ += r.events.size();
    ROS_WARN_THROTTLE(5.0,
                      "asynevo: the estimator is behind by %llu queued events (max_queue_events %d): dropped a "
                      "message of %zu events (%llu messages so far)",
                      static_cast<unsigned long long>(queued_events_), options_.max_queue_events, r.events.size(),
                      static_cast<unsigned long long>(dropped_overload_));
    return;
  }
  ++messages_accepted_;
  stream_.has_last = true;
  stream_.last_t_ns = r.events.back().t_ns;
  queued_events_ += r.events.size();
  queue_.push_back(Batch{std::move(r.events), arrived});
  lock.unlock();
  wake_.notify_one();
}

void OdometryNode::work() {
  for (;;) {
    Batch batch;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and the queue is processed
      batch = std::move(queue_.front());
      queue_.pop_front();
    }
    try {
      process(batch);
    } catch (const std::exception& e) {  // the estimator must not take the node down
      ROS_ERROR("asynevo: processing a message failed: %s", e.what());
    }
    std::lock_guard<std::mutex> lock(mutex_);
    queued_events_ -= batch.events.size();
  }
}

void OdometryNode::process(const Batch& batch) {
  const std::vector<Event>& ev = batch.events;
  // Slices of at most one marker period, so that every knot the estimator adds is seen (and published)
  // as the newest one.
  std::size_t begin = 0;
  while (begin < ev.size()) {
    const int64_t slice_end = (ev[begin].t_ns / kSliceNs + 1) * kSliceNs;
    std::size_t end = begin + 1;
    while (end < ev.size() && ev[end].t_ns < slice_end) ++end;
    feed_->push(ev.data() + begin, end - begin);
    publishNewKnots();
    begin = end;
  }
  const double lag = secondsSince(batch.arrived);
  const frontend::FrontendStats& f = feed_->frontendStats();
  std::lock_guard<std::mutex> lock(mutex_);
  Progress& p = progress_;
  p.events_processed += ev.size();
  p.last_processed_t_ns = ev.back().t_ns;
  p.lag_s = lag;
  p.max_lag_period_s = std::max(p.max_lag_period_s, lag);
  p.max_lag_s = std::max(p.max_lag_s, lag);
  p.initialized = feed_->estimatorStats().initialized;
  p.features = f.features_created;
  p.frontend_dropped = f.dropped_out_of_sensor + f.dropped_time_reversal;
}

void OdometryNode::publishNewKnots() {
  uint64_t newest = 0, finals = 0;
  if (const std::optional<backend::Knot> k = feed_->newestKnot(); k && k->t_ns > newest_published_t_ns_) {
    newest_published_t_ns_ = k->t_ns;
    odometry_pub_.publish(odometryMessage(*k, options_.world_frame, options_.camera_frame));
    pose_pub_.publish(poseMessage(*k, options_.world_frame));
    if (options_.publish_tf) {
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(transformMessage(*k, options_.world_frame, options_.camera_frame));
      tf_pub_.publish(tf);
    }
    newest = 1;
  }
  for (const backend::Knot& k : feed_->takeFinalKnots()) {
    pose_final_pub_.publish(poseMessage(k, options_.world_frame));
    ++finals;
  }
  if (newest + finals == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  progress_.knots_published += newest;
  progress_.final_knots_published += finals;
}

std::string OdometryNode::statsJson() {
  std::string skipped;
  uint64_t skipped_total = 0;
  for (std::size_t i = 1; i < kSkipReasons; ++i) {
    skipped += fmt::format("{}\"{}\": {}", i > 1 ? ", " : "", skipReasonName(static_cast<SkipReason>(i)), skipped_[i]);
    skipped_total += skipped_[i];
  }
  const Progress& p = progress_;
  return fmt::format(
      "{{\"messages_received\": {}, \"messages_accepted\": {}, \"events_received\": {}, \"events_processed\": {}, "
      "\"queued_events\": {}, \"lag_s\": {:.6f}, \"max_lag_s\": {:.6f}, \"event_time_behind_s\": {:.6f}, "
      "\"initialized\": {}, \"features\": {}, \"knots_published\": {}, \"final_knots_published\": {}, "
      "\"frontend_dropped_events\": {}, \"before_calibration\": {}, \"camera_info_rejected\": {}, "
      "\"dropped_overload\": {}, \"dropped_overload_events\": {}, \"skipped_total\": {}, \"skipped\": {{{}}}}}",
      messages_received_, messages_accepted_, events_received_, p.events_processed, queued_events_, p.lag_s,
      p.max_lag_s,
      stream_.has_last && p.events_processed > 0 ? (stream_.last_t_ns - p.last_processed_t_ns) * 1e-9 : 0.0,
      p.initialized ? "true" : "false", p.features, p.knots_published, p.final_knots_published, p.frontend_dropped,
      before_calibration_, camera_info_rejected_, dropped_overload_, dropped_overload_events_, skipped_total, skipped);
}

void OdometryNode::onStatsTimer(const ros::WallTimerEvent&) {
  std_msgs::String msg;
  std::lock_guard<std::mutex> lock(mutex_);
  msg.data = statsJson();
  stats_pub_.publish(msg);
  Progress& p = progress_;
  // A line while messages arrive or wait; none while the stream is idle.
  if (messages_received_ == logged_messages_ && queued_events_ == 0) return;
  logged_messages_ = messages_received_;
  uint64_t skipped_total = 0;
  for (uint64_t n : skipped_) skipped_total += n;
  ROS_INFO("asynevo: %llu events processed, %llu queued; backend lag %.3f s (max %.3f s in the last %.1f s); "
           "%s, %llu knots; %llu messages skipped, %llu dropped (overload)",
           static_cast<unsigned long long>(p.events_processed), static_cast<unsigned long long>(queued_events_),
           p.lag_s, p.max_lag_period_s, options_.stats_period_s, p.initialized ? "tracking" : "initializing",
           static_cast<unsigned long long>(p.knots_published), static_cast<unsigned long long>(skipped_total),
           static_cast<unsigned long long>(dropped_overload_));
  p.max_lag_period_s = 0;
}

void OdometryNode::finish() {
  events_sub_.shutdown();
  stats_timer_.stop();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();  // processes what is queued first
  if (feed_) {
    try {
      feed_->finish();
      publishNewKnots();
    } catch (const std::exception& e) {
      ROS_ERROR("asynevo: the final solve failed: %s", e.what());
    }
  }
  logSummary();
}

void OdometryNode::logSummary() {
  std_msgs::String msg;
  std::lock_guard<std::mutex> lock(mutex_);
  msg.data = statsJson();
  stats_pub_.publish(msg);
  ROS_INFO("asynevo: finished: %s", msg.data.c_str());
}

}  // namespace asynevo::ros_node
