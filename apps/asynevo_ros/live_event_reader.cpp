#include "live_event_reader.hpp"

#include <utility>

namespace asynevo::ros_node {

LiveEventReader::LiveEventReader(int width, int height, uint64_t max_queued_events)
    : max_queued_events_(max_queued_events) {
  info_.path = "the ROS event topic";
  info_.format = "ros";
  info_.width = width;
  info_.height = height;
  info_.size_origin = "the calibration";
}

bool LiveEventReader::push(std::vector<Event> events, Clock::time_point arrived) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ || queued_events_ + events.size() > max_queued_events_) return false;
    queued_events_ += events.size();
    queue_.push_back(Batch{std::move(events), arrived});
  }
  ready_.notify_one();
  return true;
}

void LiveEventReader::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

bool LiveEventReader::read(EventPacket& packet) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return closed_ || !queue_.empty(); });
  packet.events.clear();
  if (queue_.empty()) return false;  // closed and drained
  Batch batch = std::move(queue_.front());
  queue_.pop_front();
  queued_events_ -= batch.events.size();
  in_flight_.push_back(Arrival{batch.events.back().t_ns, batch.arrived});
  lock.unlock();
  packet.first_index = stats_.events;
  stats_.events += batch.events.size();
  packet.events = std::move(batch.events);
  return true;
}

uint64_t LiveEventReader::queuedEvents() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queued_events_;
}

std::optional<LiveEventReader::Clock::time_point> LiveEventReader::doneBefore(int64_t t_ns) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::optional<Clock::time_point> newest;
  while (!in_flight_.empty() && in_flight_.front().last_t_ns < t_ns) {
    newest = in_flight_.front().arrived;
    in_flight_.pop_front();
  }
  return newest;
}

}  // namespace asynevo::ros_node
