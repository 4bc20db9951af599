#pragma once
// Live use without the pipeline's threads: the caller pushes batches of events as they arrive and
// collects the estimate between batches (the Python streaming API, asynevo.Stream). Everything runs in
// the caller's thread, in the order the two-thread pipeline uses (docs/pipeline.md): before the first
// event at or after each time marker the estimator advances to it, then the frontend processes the
// event and its measurements go straight to the estimator. The estimator therefore sees the call
// sequence of an offline run, and the same events give the same trajectory as runDataset/runEvents,
// however they are split into batches.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/config/config.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/pipeline/pipeline.hpp"
#include "asynevo/pipeline/run.hpp"

namespace asynevo::pipeline {

class EventFeed {
 public:
  /// `config` is validated against the camera's size (ConfigError otherwise).
  EventFeed(Config config, const CameraModel& camera, BackendKind backend = BackendKind::kWindow,
            int64_t marker_period_ns = PipelineOptions{}.marker_period_ns);
  ~EventFeed();
  EventFeed(const EventFeed&) = delete;
  EventFeed& operator=(const EventFeed&) = delete;

  /// Processes `count` events (in time order, continuing the previous batches; the frontend drops and
  /// counts events outside the sensor or going back in time). Throws Error after finish().
  void push(const Event* events, std::size_t count);
  /// End of the stream: the frontend ends its features, the estimator makes its last solve and every
  /// remaining knot final. Further calls do nothing.
  void finish();
  bool finished() const { return finished_; }

  /// Knots whose estimate will not change any more, oldest first, each handed out once.
  std::vector<backend::Knot> takeFinalKnots();
  /// Landmarks the estimator let go of since the last call (all remaining ones after finish()).
  std::vector<backend::LandmarkPoint> takeFinalLandmarks();
  /// The newest knot of the sliding window (still being refined) while it tracks; nullopt before
  /// initialization, after a tracking loss or for the full-history baselines.
  std::optional<backend::Knot> newestKnot() const;

  const Config& config() const { return config_; }
  const frontend::FrontendStats& frontendStats() const { return frontend_->stats(); }
  const backend::EstimatorStats& estimatorStats() const { return estimator_->stats(); }
  const char* backendName() const { return estimator_->name(); }
  uint64_t events() const { return events_; }
  uint64_t measurements() const { return measurements_; }
  uint64_t markers() const { return markers_; }
  int64_t firstTime() const { return first_t_ns_; }
  int64_t lastTime() const { return last_t_ns_; }

 private:
  class DirectSink;
  void drain();

  Config config_;
  std::unique_ptr<frontend::Frontend> frontend_;
  std::unique_ptr<backend::Estimator> estimator_;
  std::unique_ptr<DirectSink> sink_;
  MarkerClock clock_;
  std::vector<backend::Knot> knots_;
  std::vector<backend::LandmarkPoint> landmarks_;
  uint64_t events_ = 0, measurements_ = 0, markers_ = 0;
  int64_t first_t_ns_ = 0, last_t_ns_ = 0;
  bool finished_ = false;
};

}  // namespace asynevo::pipeline
