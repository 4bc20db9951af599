#include "asynevo/pipeline/pipeline.hpp"

#include <chrono>
#include <exception>
#include <stdexcept>
#include <thread>
#include <utility>

#include "asynevo/core/time.hpp"
#include "asynevo/pipeline/bounded_queue.hpp"

namespace asynevo::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

int64_t floorMultiple(int64_t t_ns, int64_t period_ns) {
  int64_t q = t_ns / period_ns;
  if (t_ns % period_ns != 0 && t_ns < 0) --q;
  return q * period_ns;
}

/// Thrown inside the frontend thread when the backend closed the queue (it failed).
struct QueueClosed {};

/// The frontend's sink: turns its output into queue items and sends them in chunks.
class QueueSink final : public frontend::MeasurementSink {
 public:
  QueueSink(BoundedQueue<Chunk>& queue, std::size_t max_items) : queue_(queue), max_items_(max_items) {
    chunk_.reserve(max_items_);
  }
  void onMeasurement(const TrackMeasurement& m) override {
    QueueItem item;
    item.kind = QueueItem::Kind::kMeasurement;
    item.measurement = m;
    add(item);
    ++measurements;
  }
  void onFeatureEnd(const frontend::FeatureEnd& end) override {
    QueueItem item;
    item.kind = QueueItem::Kind::kFeatureEnd;
    item.measurement.feature_id = end.feature_id;
    item.measurement.t_ns = end.t_ns;
    add(item);
    ++feature_ends;
  }
  void marker(int64_t t_ns) {
    QueueItem item;
    item.kind = QueueItem::Kind::kMarker;
    item.measurement.t_ns = t_ns;
    chunk_.push_back(item);
    ++markers;
    send();
  }
  void send() {
    if (chunk_.empty()) return;
    Chunk full;
    full.reserve(max_items_);
    full.swap(chunk_);
    if (!queue_.push(std::move(full))) throw QueueClosed{};
  }

  uint64_t measurements = 0, feature_ends = 0, markers = 0;

 private:
  void add(const QueueItem& item) {
    chunk_.push_back(item);
    if (chunk_.size() >= max_items_) send();
  }
  BoundedQueue<Chunk>& queue_;
  std::size_t max_items_;
  Chunk chunk_;
};

}  // namespace

double PipelineStats::spanSeconds() const {
  return events > 0 ? durationSeconds(first_t_ns, last_t_ns) : 0.0;
}

double PipelineStats::realTimeFactor() const {
  const double span = spanSeconds();
  return span > 0 ? wall_seconds / span : 0.0;
}

MarkerClock::MarkerClock(int64_t period_ns) : period_ns_(period_ns) {
  if (period_ns <= 0) throw std::invalid_argument("MarkerClock: the period must be positive");
}

bool MarkerClock::next(int64_t t_ns, int64_t& marker_ns) {
  if (!started_) {
    started_ = true;
    next_ns_ = floorMultiple(t_ns, period_ns_) + period_ns_;
    return false;
  }
  if (t_ns < next_ns_) return false;
  marker_ns = floorMultiple(t_ns, period_ns_);
  next_ns_ = marker_ns + period_ns_;
  return true;
}

Pipeline::Pipeline(EventReader& reader, frontend::Frontend& frontend, backend::Estimator& estimator,
                   PipelineOutput& output, const PipelineOptions& options)
    : reader_(reader), frontend_(frontend), estimator_(estimator), output_(output), options_(options) {
  if (options_.queue_capacity == 0) options_.queue_capacity = options_.real_time ? 60000 : 1024;
  if (options_.max_chunk_items == 0)
    throw std::invalid_argument("Pipeline: max_chunk_items must be positive");
  if (!(options_.speed > 0)) throw std::invalid_argument("Pipeline: speed must be positive");
}

PipelineStats Pipeline::run(const std::function<void(const PipelineProgress&)>& progress) {
  PipelineStats stats;
  stats.real_time = options_.real_time;
  stats.queue_capacity = options_.queue_capacity;
  BoundedQueue<Chunk> queue(options_.queue_capacity);
  std::atomic<int64_t> newest_marker{0};
  std::atomic<int64_t> processed_marker{0};
  std::atomic<bool> abort{false};
  std::exception_ptr backend_error;
  int64_t max_lag = 0;
  double lag_sum = 0;
  uint64_t lag_samples = 0;
  double backend_busy = 0;

  const auto start = Clock::now();

  // The backend thread: the estimator and the outputs, in queue order.
  std::thread backend_thread([&] {
    try {
      auto drain = [&] {
        auto knots = estimator_.takeFinalKnots();
        if (!knots.empty()) output_.onFinalKnots(knots);
        auto records = estimator_.takeUpdateRecords();
        if (!records.empty()) output_.onUpdateRecords(records);
        auto landmarks = estimator_.takeFinalLandmarks();
        if (!landmarks.empty()) output_.onLandmarks(landmarks);
      };
      while (std::optional<Chunk> chunk = queue.pop()) {
        if (abort.load()) return;
        const auto busy_start = Clock::now();
        for (const QueueItem& item : *chunk) {
          switch (item.kind) {
            case QueueItem::Kind::kMeasurement:
              output_.onMeasurement(item.measurement);
              estimator_.addMeasurement(item.measurement);
              break;
            case QueueItem::Kind::kFeatureEnd:
              estimator_.endFeature(item.measurement.feature_id);
              break;
            case QueueItem::Kind::kMarker: {
              output_.onMarker(item.measurement.t_ns);
              estimator_.advanceTo(item.measurement.t_ns);
              drain();
              processed_marker.store(item.measurement.t_ns);
              const int64_t lag = newest_marker.load() - item.measurement.t_ns;
              if (lag > max_lag) max_lag = lag;
              lag_sum += static_cast<double>(lag);
              ++lag_samples;
              break;
            }
          }
        }
        backend_busy += std::chrono::duration<double>(Clock::now() - busy_start).count();
      }
      if (abort.load()) return;
      const auto busy_start = Clock::now();
      estimator_.finish();
      auto knots = estimator_.takeFinalKnots();
      if (!knots.empty()) output_.onFinalKnots(knots);
      auto records = estimator_.takeUpdateRecords();
      if (!records.empty()) output_.onUpdateRecords(records);
      auto landmarks = estimator_.takeFinalLandmarks();
      if (!landmarks.empty()) output_.onLandmarks(landmarks);
      backend_busy += std::chrono::duration<double>(Clock::now() - busy_start).count();
    } catch (...) {
      backend_error = std::current_exception();
      queue.close();  // wakes a frontend waiting for room; its next push fails
    }
  });

  // The frontend, in this thread.
  std::exception_ptr frontend_error;
  QueueSink sink(queue, options_.max_chunk_items);
  try {
    MarkerClock clock(options_.marker_period_ns);
    EventPacket packet;
    bool first = true;
    while (reader_.read(packet)) {
      ++stats.packets;
      const std::size_t count = packet.events.size();
      for (std::size_t i = 0; i < count; ++i) {
        const Event& e = packet.events[i];
        // The frontend's per-pixel maps of an event a few places later start loading now.
        if (i + frontend::Frontend::kPrefetchAhead < count)
          frontend_.prefetch(packet.events[i + frontend::Frontend::kPrefetchAhead]);
        if (first) {
          stats.first_t_ns = e.t_ns;
          first = false;
        }
        int64_t marker = 0;
        if (clock.next(e.t_ns, marker)) {
          if (options_.real_time) {
            const auto due = start + std::chrono::nanoseconds(static_cast<int64_t>(
                                         static_cast<double>(marker - stats.first_t_ns) / options_.speed));
            const auto now = Clock::now();
            if (now < due) {
              std::this_thread::sleep_until(due);
            } else {
              const int64_t behind = std::chrono::duration_cast<std::chrono::nanoseconds>(now - due).count();
              if (behind > stats.max_pacing_behind_ns) stats.max_pacing_behind_ns = behind;
            }
          }
          newest_marker.store(marker);
          sink.marker(marker);
        }
        frontend_.process(e, sink);
        if (e.t_ns > stats.last_t_ns || stats.events == 0) stats.last_t_ns = e.t_ns;
        ++stats.events;
      }
      if (progress) {
        PipelineProgress p;
        p.events = stats.events;
        p.first_t_ns = stats.first_t_ns;
        p.event_t_ns = stats.last_t_ns;
        p.backend_t_ns = processed_marker.load();
        p.lag_ns = newest_marker.load() - p.backend_t_ns;
        progress(p);
      }
    }
    frontend_.finish(sink);
    sink.send();
  } catch (const QueueClosed&) {
    // The backend failed; its error is rethrown below.
  } catch (...) {
    frontend_error = std::current_exception();
    abort.store(true);
  }
  stats.frontend_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  queue.close();
  backend_thread.join();
  stats.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (frontend_error) std::rethrow_exception(frontend_error);
  if (backend_error) std::rethrow_exception(backend_error);

  stats.markers = sink.markers;
  stats.measurements = sink.measurements;
  stats.feature_ends = sink.feature_ends;
  stats.queue_high_water = queue.highWater();
  stats.queue_push_waits = queue.pushWaits();
  stats.queue_pop_waits = queue.popWaits();
  stats.max_lag_ns = max_lag;
  stats.mean_lag_ns = lag_samples > 0 ? lag_sum / static_cast<double>(lag_samples) : 0.0;
  stats.backend_busy_seconds = backend_busy;
  return stats;
}

}  // namespace asynevo::pipeline
