#pragma once
// The node's messages as an EventReader, so that the two-thread pipeline of `asynevo run`
// (pipeline::Pipeline: frontend in the reading thread, estimator in a second one) runs on a live stream.
// The subscription callback push()es checked batches; read() blocks until one is there and returns false
// once close() was called and every batch was handed out. The arrival time of each batch is kept until the
// estimator has passed its last event, which gives the node's lag: message arrival to estimator done.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include "asynevo/io/event_reader.hpp"

namespace asynevo::ros_node {

class LiveEventReader final : public EventReader {
 public:
  using Clock = std::chrono::steady_clock;

  /// `max_queued_events`: push() refuses a batch that would make more events wait than this.
  LiveEventReader(int width, int height, uint64_t max_queued_events);

  /// Queues a batch (non-empty, in time order after the previous one; the caller checked it). Returns false,
  /// queuing nothing, when it would exceed max_queued_events or after close().
  bool push(std::vector<Event> events, Clock::time_point arrived);
  /// End of the stream: read() returns false once the queue is empty.
  void close();

  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

  /// Events waiting to be read.
  uint64_t queuedEvents() const;
  /// Called when the estimator reached time marker `t_ns` (every event before it is processed): the arrival
  /// time of the newest batch that ended before it, if one ended since the last call.
  std::optional<Clock::time_point> doneBefore(int64_t t_ns);

 private:
  struct Batch {
    std::vector<Event> events;
    Clock::time_point arrived;
  };
  struct Arrival {
    int64_t last_t_ns;
    Clock::time_point arrived;
  };

  StreamInfo info_;
  ReaderStats stats_;  // read() only (the pipeline's reading thread)
  const uint64_t max_queued_events_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Batch> queue_;
  uint64_t queued_events_ = 0;
  bool closed_ = false;
  std::deque<Arrival> in_flight_;  // batches handed to the frontend, oldest first
};

}  // namespace asynevo::ros_node
