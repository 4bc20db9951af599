#include "asynevo/pipeline/event_feed.hpp"

#include <utility>

#include "asynevo/backend/sliding_window_estimator.hpp"
#include "asynevo/core/error.hpp"

namespace asynevo::pipeline {

/// The frontend's sink: hands measurements and feature ends straight to the estimator, as the
/// pipeline's backend thread does with queue items.
class EventFeed::DirectSink final : public frontend::MeasurementSink {
 public:
  DirectSink(backend::Estimator& estimator, uint64_t& measurements)
      : estimator_(estimator), measurements_(measurements) {}
  void onMeasurement(const TrackMeasurement& m) override {
    estimator_.addMeasurement(m);
    ++measurements_;
  }
  void onFeatureEnd(const frontend::FeatureEnd& end) override { estimator_.endFeature(end.feature_id); }

 private:
  backend::Estimator& estimator_;
  uint64_t& measurements_;
};

EventFeed::EventFeed(Config config, const CameraModel& camera, BackendKind backend, int64_t marker_period_ns)
    : config_(std::move(config)), clock_(marker_period_ns) {
  config_.sensor.width = camera.width();
  config_.sensor.height = camera.height();
  config_.validate();
  config_.validateForSensor();
  frontend_ = std::make_unique<frontend::Frontend>(config_.frontend, camera);
  estimator_ = makeEstimator(backend, config_, camera, *frontend_, false);
  sink_ = std::make_unique<DirectSink>(*estimator_, measurements_);
}

EventFeed::~EventFeed() = default;

void EventFeed::push(const Event* events, std::size_t count) {
  if (finished_) throw Error("EventFeed: events pushed after finish()");
  for (std::size_t i = 0; i < count; ++i) {
    const Event& e = events[i];
    // The frontend's per-pixel maps of an event a few places later start loading now.
    if (i + frontend::Frontend::kPrefetchAhead < count)
      frontend_->prefetch(events[i + frontend::Frontend::kPrefetchAhead]);
    if (events_ == 0) first_t_ns_ = e.t_ns;
    int64_t marker = 0;
    if (clock_.next(e.t_ns, marker)) {
      estimator_->advanceTo(marker);
      ++markers_;
      drain();
    }
    frontend_->process(e, *sink_);
    if (e.t_ns > last_t_ns_ || events_ == 0) last_t_ns_ = e.t_ns;
    ++events_;
  }
}

void EventFeed::finish() {
  if (finished_) return;
  finished_ = true;
  frontend_->finish(*sink_);
  estimator_->finish();
  drain();
}

void EventFeed::drain() {
  for (backend::Knot& k : estimator_->takeFinalKnots()) knots_.push_back(std::move(k));
  estimator_->takeUpdateRecords();
  for (backend::LandmarkPoint& l : estimator_->takeFinalLandmarks()) landmarks_.push_back(std::move(l));
}

std::vector<backend::Knot> EventFeed::takeFinalKnots() { return std::exchange(knots_, {}); }

std::vector<backend::LandmarkPoint> EventFeed::takeFinalLandmarks() { return std::exchange(landmarks_, {}); }

std::optional<backend::Knot> EventFeed::newestKnot() const {
  const auto* window = dynamic_cast<const backend::SlidingWindowEstimator*>(estimator_.get());
  if (window == nullptr || !window->tracking() || window->trajectory().empty()) return std::nullopt;
  return window->trajectory().knots().rbegin()->second;
}

}  // namespace asynevo::pipeline
