#pragma once
// The two-thread pipeline (DESIGN.md §4 Threads; docs/pipeline.md): the calling thread reads events
// and runs the frontend, a second thread runs the estimator, and a bounded queue joins them.
//
// What crosses the queue is a sequence of items: measurements and feature ends in the order the
// frontend produced them, and a time marker M each time event time reaches the next multiple of
// `marker_period_ns` (before the first event at or after M is processed, so every event earlier than M
// has been seen). The backend calls estimator.addMeasurement / endFeature / advanceTo(M) in exactly
// this order. The sequence depends only on the events and the configuration — not on packet sizes,
// queue capacity or thread timing — so in offline mode two runs give identical outputs.
//
// Offline mode (default): the frontend blocks when the queue is full. Real-time mode: events are
// released no faster than their timestamps allow against the wall clock (scaled by `speed`), the
// queue is larger, and the backend's lag (newest marker − marker it has processed) is measured.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/event_reader.hpp"

namespace asynevo::pipeline {

struct PipelineOptions {
  bool real_time = false;                ///< pace events by their timestamps against the wall clock
  double speed = 1.0;                    ///< real-time mode: playback rate (2 = twice as fast)
  int64_t marker_period_ns = 1'000'000;  ///< time markers at every multiple of this (1 ms)
  std::size_t queue_capacity = 0;        ///< chunks; 0 = 1024 offline (~1 s of event time), 60000 real time
  std::size_t max_chunk_items = 1024;    ///< a chunk is sent at each marker or when it holds this many items
};

/// One element of the frontend → backend sequence.
struct QueueItem {
  enum class Kind : uint8_t { kMeasurement, kFeatureEnd, kMarker };
  Kind kind = Kind::kMarker;
  /// kMeasurement: the measurement; kFeatureEnd: feature_id and t_ns (decision time); kMarker: t_ns.
  TrackMeasurement measurement;
};
/// Items travel in chunks (one per marker period at most) so the queue's lock is taken rarely.
using Chunk = std::vector<QueueItem>;

/// Receives the outputs, in the backend thread, in a deterministic order (offline mode): each
/// measurement as the backend takes it, then what the estimator hands out after each advanceTo() and
/// after finish().
class PipelineOutput {
 public:
  virtual ~PipelineOutput() = default;
  virtual void onMeasurement(const TrackMeasurement& /*m*/) {}
  /// A time marker, just before the estimator advances to it.
  virtual void onMarker(int64_t /*t_ns*/) {}
  virtual void onFinalKnots(const std::vector<backend::Knot>& /*knots*/) {}
  virtual void onUpdateRecords(const std::vector<backend::UpdateRecord>& /*records*/) {}
  virtual void onLandmarks(const std::vector<backend::LandmarkPoint>& /*landmarks*/) {}
};

/// A snapshot for a progress display (called in the frontend thread after every packet).
struct PipelineProgress {
  uint64_t events = 0;
  int64_t first_t_ns = 0;    ///< first event time
  int64_t event_t_ns = 0;    ///< newest event time read
  int64_t backend_t_ns = 0;  ///< newest marker the backend has processed
  int64_t lag_ns = 0;        ///< newest marker sent − newest marker processed
};

struct PipelineStats {
  uint64_t events = 0;
  uint64_t packets = 0;
  int64_t first_t_ns = 0;
  int64_t last_t_ns = 0;
  uint64_t markers = 0;
  uint64_t measurements = 0;
  uint64_t feature_ends = 0;
  double wall_seconds = 0;          ///< whole run, both threads
  double frontend_seconds = 0;      ///< reading + frontend (+ pacing sleeps, + waits for the queue)
  double backend_busy_seconds = 0;  ///< time the backend thread spent in the estimator and the output
  std::size_t queue_capacity = 0;
  std::size_t queue_high_water = 0;  ///< most chunks waiting at once
  uint64_t queue_push_waits = 0;     ///< the frontend waited for room (backend slower)
  uint64_t queue_pop_waits = 0;      ///< the backend waited for input (frontend slower)
  int64_t max_lag_ns = 0;            ///< largest backend lag seen at a marker
  double mean_lag_ns = 0;            ///< mean over markers
  int64_t max_pacing_behind_ns = 0;  ///< real time: how far the frontend fell behind the wall clock
  bool real_time = false;

  double spanSeconds() const;
  /// Wall time ÷ event-time span (< 1: faster than real time); 0 for an empty span.
  double realTimeFactor() const;
};

class Pipeline {
 public:
  /// The references must outlive run(). The frontend and estimator must be fresh.
  Pipeline(EventReader& reader, frontend::Frontend& frontend, backend::Estimator& estimator,
           PipelineOutput& output, const PipelineOptions& options = {});

  /// Reads the whole stream: frontend in this thread, estimator in a second one; calls
  /// estimator.finish() at the end. An exception in either thread stops both and is rethrown here
  /// (outputs already handed to `output` stay written).
  PipelineStats run(const std::function<void(const PipelineProgress&)>& progress = {});

 private:
  EventReader& reader_;
  frontend::Frontend& frontend_;
  backend::Estimator& estimator_;
  PipelineOutput& output_;
  PipelineOptions options_;
};

/// The event-time marker sequence, separated out so it can be tested: feed event times in order,
/// get the marker to emit before the event (if any). Markers are the multiples of the period; when
/// event time jumps over several, one marker (the largest multiple reached) is emitted.
class MarkerClock {
 public:
  explicit MarkerClock(int64_t period_ns);
  /// Returns true and sets `marker_ns` when `t_ns` reaches the next multiple of the period.
  bool next(int64_t t_ns, int64_t& marker_ns);
  int64_t period() const { return period_ns_; }

 private:
  int64_t period_ns_;
  bool started_ = false;
  int64_t next_ns_ = 0;
};

}  // namespace asynevo::pipeline
