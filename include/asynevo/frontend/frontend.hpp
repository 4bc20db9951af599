#pragma once
// The asynchronous event-driven frontend (DESIGN.md §4 Frontend; docs/frontend.md): per event, in one
// thread,
//  1. validate (inside the sensor; time not going back by more than a tolerance), update the
//     refractory-filter maps and the SAE for every valid event;
//  2. dispatch the event through a coarse grid to the HASTE trackers whose circle contains it; on a
//     state change move the feature in the registration table, resolve collisions (the older feature
//     stays), drop it near the border, record a measurement if min_dt passed since its last one;
//  3. otherwise, when fewer than max_features are active, run the corner detector; a corner seeds a
//     feature when the registration table holds no feature within min_distance (patch search);
//  4. every housekeeping period of event time drop features that are idle, that never initialized,
//     or that fail a quality test: window events spread along a line (an edge, where HASTE slides),
//     drift from the first template (a reference the tracker cannot pull along), or a patch rotation
//     inconsistent with the common rotation of all features (sliding around a curved contour);
//  5. every neighbour_check_ms (when enabled) drop features whose recent displacement disagrees with the
//     median displacement of their nearest neighbours (creeping over a soft texture).
// Trackers work in raw pixel coordinates; measurements carry raw pixels and normalized undistorted
// coordinates interpolated from an injected per-pixel undistortion table.
// After construction nothing is allocated per event (trackers live in a fixed pool).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/camera/undistortion_table.hpp"
#include "asynevo/core/config/frontend_config.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/frontend/corner_detector.hpp"
#include "asynevo/frontend/event_filter.hpp"
#include "asynevo/frontend/event_rate_budget.hpp"
#include "asynevo/frontend/haste_tracker.hpp"
#include "asynevo/frontend/sae.hpp"
#include "asynevo/frontend/track_measurement.hpp"
#include "asynevo/frontend/tracking_frame.hpp"

namespace asynevo::frontend {

/// Why a feature ended.
enum class DropReason : uint8_t {
  kBorder,       ///< its position came within border_margin_px of the image border
  kCollision,    ///< it came within collision_radius_px of an older feature
  kIdle,         ///< no state change for max_idle_ms
  kInitTimeout,  ///< its tracker did not fill its first window within init_timeout_ms
  kQuality,      ///< quality test failed (edge-like window: drift risk)
  kUnhealthy,    ///< the tracker's template lost its mass (numerical guard)
  kFinished,     ///< the stream ended (finish())
  kDrift,        ///< its window matches its first template away from its state (slid or lost)
  kRotation,     ///< its patch rotated away from the features' common rotation (slid around a curve)
  kNeighbour,    ///< its recent displacement disagrees with its nearest neighbours' (neighbour-motion test)
};
constexpr int kDropReasonCount = 10;
const char* dropReasonName(DropReason reason);

struct FeatureEnd {
  int64_t feature_id = 0;
  int64_t t_ns = 0;  ///< event time of the decision
  DropReason reason = DropReason::kFinished;
  uint32_t measurements = 0;  ///< measurements recorded for it
};

/// Receives the frontend's output as it is produced.
class MeasurementSink {
 public:
  virtual ~MeasurementSink() = default;
  virtual void onMeasurement(const TrackMeasurement& m) = 0;
  virtual void onFeatureEnd(const FeatureEnd& /*end*/) {}
};

/// A sink that keeps everything (tests, tools, small files).
class MeasurementCollector final : public MeasurementSink {
 public:
  void onMeasurement(const TrackMeasurement& m) override { measurements.push_back(m); }
  void onFeatureEnd(const FeatureEnd& end) override { ends.push_back(end); }
  std::vector<TrackMeasurement> measurements;
  std::vector<FeatureEnd> ends;
};

struct FrontendStats {
  uint64_t events = 0;                 ///< events received
  uint64_t dropped_out_of_sensor = 0;  ///< outside width x height
  uint64_t dropped_time_reversal = 0;  ///< earlier than the newest by more than the tolerance
  uint64_t clamped_time = 0;           ///< slightly earlier: processed at the newest time
  uint64_t dropped_hot_pixel = 0;      ///< from a pixel the hot-pixel filter masked
  uint64_t dropped_noise_filter = 0;   ///< without support in the background-activity filter
  uint64_t events_shed = 0;            ///< shed by the peak-rate budget (max_event_rate_mev_s)
  uint64_t detections_skipped = 0;     ///< events over the budget that would have reached the detector
  uint64_t filter_accepted = 0;        ///< passed the refractory filter
  uint64_t detector_runs = 0;          ///< events that reached the corner detector
  uint64_t candidates = 0;             ///< Arc* candidates among them
  uint64_t corners = 0;                ///< corners among them
  uint64_t tracker_updates = 0;        ///< (event, tracker) pairs inside a tracker's circle
  uint64_t state_changes = 0;
  uint64_t measurements = 0;
  uint64_t measurements_without_undistortion = 0;  ///< skipped: invalid undistortion table entry
  /// events of a pixel without a rectified position (its undistortion did not converge): counted, not
  /// tracked or detected
  uint64_t events_without_position = 0;
  uint64_t subpixel_fit_failures = 0;  ///< template_fit ended too far off: the parabola's offset used
  uint64_t features_created = 0;
  uint64_t neighbour_tests = 0;  ///< features evaluated by the neighbour-motion test (all checks)
  std::array<uint64_t, kDropReasonCount> features_dropped{};
  int active_features = 0;
  int max_active_features = 0;
  double active_feature_seconds = 0;  ///< integral of the active count over event time
  /// event time [s] spent at each active count (index = count): the distribution over time
  std::vector<double> seconds_at_active_count;
  double harris_threshold = 0;        ///< the FA-Harris threshold now (adaptive detection)
  double min_harris_threshold = 0;    ///< the lowest it went
  int64_t first_t_ns = 0;
  int64_t last_t_ns = 0;

  double spanSeconds() const;
  /// Count per second of event time (0 for an empty span).
  double perSecond(uint64_t count) const;
  double meanActiveFeatures() const;
  /// The active count that the features were at or below for at least `fraction` of the event time
  /// (0.5: the median over time); 0 before any event time has passed.
  int activeFeaturesQuantile(double fraction) const;
  /// Multi-line human-readable summary.
  std::string summary() const;
};

class Frontend {
 public:
  /// `undistortion` maps raw pixels to normalized undistorted coordinates (CameraModel::
  /// undistortionTable<float>()); an empty table means identity (xn = x, yn = y), for tests.
  Frontend(const FrontendConfig& config, int width, int height, UndistortionTable<float> undistortion = {});
  /// A frontend for `camera`'s sensor: measurements undistorted through its model; the trackers work in
  /// the rectified frame when FrontendConfig::rectified_tracking is on (tracking_frame.hpp).
  Frontend(const FrontendConfig& config, const CameraModel& camera);
  ~Frontend();
  Frontend(const Frontend&) = delete;
  Frontend& operator=(const Frontend&) = delete;

  /// The binning factor b (FrontendConfig::binning with auto resolved) for a sensor of this size.
  static int binningFor(const FrontendConfig& config, int width, int height);
  /// The corner detector's parameters of `config` (its detector and threshold, before any adaptation).
  static DetectorParams detectorParams(const FrontendConfig& config);
  /// b: the frontend works on a (width / b) x (height / b) image (FrontendConfig::binning).
  int binning() const { return 1 << bin_shift_; }

  /// An event in sensor pixels (binned here when binning > 1).
  void process(const Event& e, MeasurementSink& sink);
  /// Events in order; while one is processed, the per-pixel maps of one a few places later are
  /// prefetched (prefetch()). Same results as one process() call per event.
  void process(const Event* events, std::size_t count, MeasurementSink& sink) {
    for (std::size_t i = 0; i < count; ++i) {
      if (i + kPrefetchAhead < count) prefetch(events[i + kPrefetchAhead]);
      process(events[i], sink);
    }
  }
  void process(const EventPacket& packet, MeasurementSink& sink) {
    process(packet.events.data(), packet.events.size(), sink);
  }
  /// Hint: `e` is processed soon (callers feeding events one by one pass the event kPrefetchAhead
  /// places later). Starts loading the entries of its pixel in the frontend's per-pixel maps (larger
  /// than the caches at 640x480; events arrive at random pixels) into the cache. No effect on results.
  void prefetch(const Event& e) const {
    if (e.x >= sensor_width_ || e.y >= sensor_height_) return;
    const std::size_t i = static_cast<std::size_t>(e.y >> bin_shift_) * width_ + (e.x >> bin_shift_);
    prefetchLine(&pixel_events_[i]);
    sae_.prefetch(i, polarityIndex(e));
  }
  /// How many events ahead process(events, count) prefetches.
  static constexpr std::size_t kPrefetchAhead = 4;
  /// Ends every active feature (reason kFinished) at the newest event time.
  void finish(MeasurementSink& sink);

  const FrontendStats& stats() const { return stats_; }
  int activeFeatures() const { return stats_.active_features; }
  const SurfaceOfActiveEvents& sae() const { return sae_; }
  /// Feature id registered at a cell of the tracking frame's grid (a pixel in the raw frame), or -1.
  int64_t registeredAt(int x, int y) const {
    return registration_[static_cast<std::size_t>(y) * frame_.gridWidth() + x];
  }
  /// The coordinates the trackers work in (their states, FeatureView::state).
  const TrackingFrame& trackingFrame() const { return frame_; }

  struct FeatureView {
    int64_t id;
    TrackerState state;
    bool initialized;
  };
  /// The active features (allocates; not for the hot path).
  std::vector<FeatureView> features() const;

  /// The tracker of an active feature, or nullptr (introspection for tests and tools).
  const HasteTracker* tracker(int64_t id) const {
    const int slot = id_map_.find(id);
    return slot < 0 ? nullptr : slots_[static_cast<std::size_t>(slot)].tracker.get();
  }

  /// Pixels the hot-pixel filter masked (x, y), in the order found; empty when it is off. With binning,
  /// the filter works on bins: each is given by its first sensor pixel (here and in dominantPixels).
  std::vector<std::pair<int, int>> hotPixels() const;

  struct PixelCount {
    int x, y;
    uint64_t events;
  };
  /// The fewest pixels (at most `max_pixels`, busiest first) that together sent more than `share` of
  /// the events inside the sensor; empty when `max_pixels` pixels do not reach that share (a stream
  /// dominated by a few pixels: hot pixels, a flickering light).
  std::vector<PixelCount> dominantPixels(double share, int max_pixels) const;

 private:
  /// The shared constructor: `frame` when given, else the raw frame with `undistortion`.
  Frontend(const FrontendConfig& config, int width, int height, UndistortionTable<float> undistortion,
           std::optional<TrackingFrame> frame);

  struct PositionSample {
    int64_t t_ns;
    float x, y;
  };
  static constexpr int kHistoryCapacity = 128;
  /// Neighbour-motion test: displacements are compared over [now - lag - window, now - lag] so that the
  /// trackers' states (middle-of-window times, ~96 in-range events behind the newest event) have caught up.
  static constexpr int64_t kNeighbourLagNs = 10'000'000;
  /// A feature younger than the window is compared over its own life, once that is this long.
  static constexpr int64_t kNeighbourMinSpanNs = 10'000'000;
  struct Candidate {  ///< a feature taking part in one neighbour-motion check
    int slot;
    float x, y;        ///< current position (neighbour search)
    int64_t first_ns;  ///< state time of its oldest remembered position
  };

  struct Slot {
    std::unique_ptr<HasteTracker> tracker;
    int64_t id = -1;  ///< -1: free
    int64_t created_ns = 0;
    int64_t last_change_ns = 0;
    uint64_t scene_changes_at_last_change = 0;  ///< stats_.state_changes at its last state change
    int64_t last_recorded_ns = 0;
    bool recorded = false;
    int reg_index = -1;  ///< registration-table index it occupies, or -1
    int cell = -1;       ///< dispatch-grid cell
    int next_in_cell = -1;
    float x = 0.f, y = 0.f;  ///< its tracker's state().x, y (the dispatch's range test reads them here)
    uint32_t measurements = 0;
    int64_t next_drift_check_ns = 0;
    float roll_at_init = 0.f;  ///< common roll when its tracker initialized
    /// Ring of its recent states (state time, position), one per state change, for the neighbour-motion
    /// test; allocated once (kHistoryCapacity).
    std::vector<PositionSample> history;
    int history_head = 0;  ///< index of the oldest sample
    int history_size = 0;
  };
  /// id -> slot, open addressing with linear probing; fixed capacity, no allocation after construction.
  class IdMap {
   public:
    explicit IdMap(int max_entries);
    void insert(int64_t id, int slot);
    int find(int64_t id) const;
    void erase(int64_t id);

   private:
    std::size_t home(int64_t id) const {
      return (static_cast<uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> shift_;
    }
    std::vector<int64_t> keys_;
    std::vector<int> values_;
    std::size_t mask_;
    int shift_;
  };

  void housekeeping(int64_t t_ns, MeasurementSink& sink);
  /// Whether the scene moved at least `px` on average since the frontend's state-change count was
  /// `changes_at`: that many state changes per feature of `features` (at least one).
  bool sceneMovedSince(uint64_t changes_at, double px, int features) const;
  /// Adaptive detection (harris_threshold_floor): one step of the threshold toward more or fewer corners.
  void adaptDetectionThreshold(int64_t t_ns);
  void updateCommonRoll();
  /// A feature's rotation since initialization minus the common rotation since then (wrapped).
  float rollDeparture(const Slot& s) const;
  void onStateChange(int slot, int64_t t_ns, MeasurementSink& sink);
  /// Position of a feature at state time t from its history (linear between state changes); false when
  /// its history does not reach back to t.
  bool positionAt(const Slot& s, int64_t t_ns, float& x, float& y) const;
  void neighbourCheck(int64_t t_ns, MeasurementSink& sink);
  /// Similarity model of the neighbour-motion test: carries each neighbour's displacement (neighbour_dx_,
  /// _dy_, positions at t_a in neighbour_ax_, _ay_) to the feature at (xa, ya). Returns the length of the
  /// similarity's correction at the feature relative to the neighbours' mean position (0 when too few
  /// pairs leave the displacements as they are).
  float carryToFeature(float xa, float ya);
  /// A new feature at the corner event `e`, whose tracking-frame position is (x, y).
  void trySeed(const Event& e, float x, float y);
  void drop(int slot, DropReason reason, int64_t t_ns, MeasurementSink& sink);
  void cellInsert(int slot, int cell);
  void cellRemove(int slot);
  /// Dispatch cell of a tracking-frame grid position (position minus the frame's origin).
  int cellOf(int x, int y) const { return (y >> kCellShift) * grid_w_ + (x >> kCellShift); }

  static constexpr int kCellShift = 4;  ///< 16 px cells >= the tracker radius (15): 3x3 cells suffice

  FrontendConfig config_;
  int bin_shift_;       ///< log2 of the binning factor
  int sensor_width_;    ///< the sensor's size (events arrive in its pixels)
  int sensor_height_;
  int width_;           ///< the binned image the frontend works on
  int height_;
  TrackingFrame frame_;
  bool fit_subpixel_;  ///< subpixel_method is template_fit
  /// neighbour_motion_model: the reference of the neighbour-motion test
  enum class NeighbourModel { kTranslation, kSimilarity, kEither } neighbour_model_;
  float similarity_min_px_;  ///< neighbour_similarity_min_px
  float similarity_agreement_px_;  ///< neighbour_similarity_agreement_px
  std::unique_ptr<HotPixelFilter> hot_pixel_filter_;        ///< null when off
  std::unique_ptr<BackgroundActivityFilter> noise_filter_;  ///< null when off
  std::unique_ptr<EventRateBudget> rate_budget_;           ///< null when off
  SurfaceOfActiveEvents sae_;
  CornerDetector detector_;
  std::vector<int64_t> registration_;  ///< feature ids on the tracking frame's grid, -1 = empty
  std::vector<uint32_t> pixel_events_;  ///< W x H events received per pixel (saturating)
  std::vector<Slot> slots_;
  std::vector<int> free_slots_;
  IdMap id_map_;
  int grid_w_;
  int grid_h_;
  std::vector<int> cell_heads_;
  std::vector<std::pair<int, int64_t>> changed_;  ///< (slot, id) whose state changed on this event
  std::vector<float> roll_scratch_;  ///< per-slot values for the median of the common roll, allocated once
  float common_roll_ = 0.f;          ///< median in-plane rotation of the features (radians, wrapped)
  // Neighbour-motion test scratch, allocated once.
  std::vector<Candidate> candidates_;
  std::vector<std::pair<float, int>> neighbour_d2_;
  std::vector<float> neighbour_dx_, neighbour_dy_;
  std::vector<float> neighbour_ax_, neighbour_ay_;  ///< the neighbours' positions at t_a
  std::vector<float> median_x_, median_y_;           ///< copies the medians reorder
  std::vector<float> pair_angle_, pair_log_scale_;  ///< similarity model: per neighbour pair
  std::vector<int> neighbour_drops_;
  int64_t next_neighbour_check_ns_ = 0;
  int64_t next_id_ = 0;
  int64_t newest_t_ns_ = 0;
  bool started_ = false;
  int64_t next_housekeeping_ns_ = 0;
  int64_t next_threshold_update_ns_ = 0;  ///< adaptive detection: event time of the next step
  int64_t last_housekeeping_ns_ = 0;
  // Parameters in ns / px, derived once.
  int64_t max_reversal_ns_;
  int64_t min_dt_ns_;
  int64_t max_idle_ns_;
  int64_t init_timeout_ns_;
  int64_t init_timeout_max_ns_;
  int64_t housekeeping_ns_;
  int64_t drift_check_ns_;
  int64_t neighbour_check_ns_;
  int64_t neighbour_window_ns_;
  float max_rotation_rad_;
  float border_margin_;
  double min_distance_px_;     ///< config.min_distance_px x config.distanceScale
  double neighbour_radius_px_;  ///< config.neighbour_radius_px x config.distanceScale
  FrontendStats stats_;
};

}  // namespace asynevo::frontend
