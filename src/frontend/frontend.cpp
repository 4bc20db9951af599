// Feature management of the event-driven frontend: registration table, id -> tracker map, dispatch
// grid, patch search, collisions, border/idle/time-out/quality removal, measurement throttling.
// Design: DESIGN.md §4 and shared/reference/frontend.md §10.5; decisions in docs/frontend.md.
#include "asynevo/frontend/frontend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::frontend {

/// The peak-rate budget's window of event time (event_rate_budget.hpp).
constexpr int64_t kRateWindowNs = 1'000'000;

const char* dropReasonName(DropReason reason) {
  switch (reason) {
    case DropReason::kBorder:
      return "border";
    case DropReason::kCollision:
      return "collision";
    case DropReason::kIdle:
      return "idle";
    case DropReason::kInitTimeout:
      return "init_timeout";
    case DropReason::kQuality:
      return "quality";
    case DropReason::kUnhealthy:
      return "unhealthy";
    case DropReason::kFinished:
      return "finished";
    case DropReason::kDrift:
      return "drift";
    case DropReason::kRotation:
      return "rotation";
    case DropReason::kNeighbour:
      return "neighbour";
  }
  return "?";
}

double FrontendStats::spanSeconds() const {
  return events == 0 ? 0.0 : durationSeconds(first_t_ns, last_t_ns);
}

double FrontendStats::perSecond(uint64_t count) const {
  const double span = spanSeconds();
  return span > 0 ? static_cast<double>(count) / span : 0.0;
}

double FrontendStats::meanActiveFeatures() const {
  const double span = spanSeconds();
  return span > 0 ? active_feature_seconds / span : 0.0;
}

int FrontendStats::activeFeaturesQuantile(double fraction) const {
  double total = 0;
  for (double sec : seconds_at_active_count) total += sec;
  if (!(total > 0)) return 0;
  double below = 0;
  for (std::size_t count = 0; count < seconds_at_active_count.size(); ++count) {
    below += seconds_at_active_count[count];
    if (below >= fraction * total) return static_cast<int>(count);
  }
  return static_cast<int>(seconds_at_active_count.size()) - 1;
}

std::string FrontendStats::summary() const {
  std::string s;
  s += fmt::format("events            {} over {:.6f} s of event time ({:.0f} ev/s)\n", events, spanSeconds(),
                   perSecond(events));
  s += fmt::format("dropped events    {} outside the sensor, {} time reversal; {} clamped\n",
                   dropped_out_of_sensor, dropped_time_reversal, clamped_time);
  if (dropped_hot_pixel + dropped_noise_filter > 0)
    s += fmt::format("noise filters     {} events of hot pixels, {} without neighbour support dropped\n",
                     dropped_hot_pixel, dropped_noise_filter);
  if (events_shed + detections_skipped > 0)
    s += fmt::format("peak-rate budget  {} events shed, {} detections skipped\n", events_shed, detections_skipped);
  s += fmt::format("detector          {} runs, {} candidates, {} corners ({:.0f} corners/s)\n", detector_runs,
                   candidates, corners, perSecond(corners));
  s += fmt::format("trackers          {} in-range updates, {} state changes\n", tracker_updates,
                   state_changes);
  s += fmt::format(
      "features          {} created, {} active now, {:.1f} active on average, median over time {}, {} at most\n",
      features_created, active_features, meanActiveFeatures(), activeFeaturesQuantile(0.5), max_active_features);
  s += "features dropped ";
  for (int r = 0; r < kDropReasonCount; ++r)
    s += fmt::format(" {}={}", dropReasonName(static_cast<DropReason>(r)), features_dropped[r]);
  s += fmt::format("\nmeasurements      {} ({:.0f}/s), {} without undistortion\n", measurements,
                   perSecond(measurements), measurements_without_undistortion);
  if (subpixel_fit_failures > 0)
    s += fmt::format("sub-pixel fit     {} failed (the parabola's offset used)\n", subpixel_fit_failures);
  if (events_without_position > 0)
    s += fmt::format("not tracked       {} events of pixels without a rectified position\n", events_without_position);
  if (neighbour_tests > 0) s += fmt::format("neighbour test    {} feature evaluations\n", neighbour_tests);
  return s;
}

// ---- IdMap ---------------------------------------------------------------------------------------

Frontend::IdMap::IdMap(int max_entries) {
  std::size_t capacity = 16;
  int bits = 4;
  while (capacity < 4 * static_cast<std::size_t>(max_entries)) {
    capacity *= 2;
    ++bits;
  }
  keys_.assign(capacity, -1);
  values_.assign(capacity, -1);
  mask_ = capacity - 1;
  shift_ = 64 - bits;
}

void Frontend::IdMap::insert(int64_t id, int slot) {
  assert(id >= 0);
  std::size_t i = home(id);
  while (keys_[i] != -1) {
    assert(keys_[i] != id);
    i = (i + 1) & mask_;
  }
  keys_[i] = id;
  values_[i] = slot;
}

int Frontend::IdMap::find(int64_t id) const {
  for (std::size_t i = home(id);; i = (i + 1) & mask_) {
    if (keys_[i] == id) return values_[i];
    if (keys_[i] == -1) return -1;
  }
}

void Frontend::IdMap::erase(int64_t id) {
  std::size_t i = home(id);
  while (keys_[i] != id) {
    if (keys_[i] == -1) return;
    i = (i + 1) & mask_;
  }
  // Backward-shift deletion keeps probe chains intact without tombstones.
  std::size_t hole = i;
  for (std::size_t j = (i + 1) & mask_; keys_[j] != -1; j = (j + 1) & mask_) {
    const std::size_t h = home(keys_[j]);
    // Move keys_[j] into the hole if its home is not in (hole, j] cyclically.
    const bool home_in_range = hole <= j ? (h > hole && h <= j) : (h > hole || h <= j);
    if (!home_in_range) {
      keys_[hole] = keys_[j];
      values_[hole] = values_[j];
      hole = j;
    }
  }
  keys_[hole] = -1;
  values_[hole] = -1;
}

// ---- Frontend ------------------------------------------------------------------------------------

DetectorParams Frontend::detectorParams(const FrontendConfig& c) {
  DetectorParams p;
  p.kind = c.detector == "arc_star" ? DetectorKind::kArcStar : DetectorKind::kFaHarris;
  p.harris_threshold = c.harris_threshold;
  p.harris_k = c.harris_k;
  p.harris_latest = c.harris_latest;
  return p;
}

namespace {

HasteParams hasteParams(const FrontendConfig& c) {
  HasteParams p;
  p.variant =
      c.tracker == "haste_correlation_star" ? HasteVariant::kCorrelationStar : HasteVariant::kDifferenceStar;
  p.hysteresis = c.haste_hysteresis;
  p.template_update = c.haste_template_update;
  return p;
}

int64_t msToNs(double ms) { return std::llround(ms * 1e6); }

}  // namespace

int Frontend::binningFor(const FrontendConfig& config, int width, int height) {
  if (config.binning > 0) return config.binning;
  int b = 1;
  while (std::max(width, height) > 400 * b && b < 8) b *= 2;
  return b;
}

namespace {
int log2Of(int power_of_two) {
  int shift = 0;
  while ((1 << shift) < power_of_two) ++shift;
  return shift;
}
int binnedExtent(int size, int shift) { return (size + (1 << shift) - 1) >> shift; }

/// Median of a non-empty vector (reorders it).
float median(std::vector<float>& v) {
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  const float upper = v[m];
  if (v.size() % 2 == 1) return upper;
  const float lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m));
  return 0.5f * (lower + upper);
}
}  // namespace

Frontend::Frontend(const FrontendConfig& config, const CameraModel& camera)
    : Frontend(config, camera.width(), camera.height(),
               config.rectified_tracking ? UndistortionTable<float>{} : camera.undistortionTable<float>(),
               config.rectified_tracking
                   ? std::optional<TrackingFrame>(std::in_place, camera, log2Of(binningFor(config, camera.width(),
                                                                                          camera.height())))
                   : std::nullopt) {}

Frontend::Frontend(const FrontendConfig& config, int width, int height, UndistortionTable<float> undistortion)
    : Frontend(config, width, height, std::move(undistortion), std::nullopt) {}

Frontend::Frontend(const FrontendConfig& config, int width, int height, UndistortionTable<float> undistortion,
                   std::optional<TrackingFrame> frame)
    : config_(config),
      bin_shift_(log2Of(binningFor(config, width, height))),
      sensor_width_(width),
      sensor_height_(height),
      width_(binnedExtent(width, bin_shift_)),
      height_(binnedExtent(height, bin_shift_)),
      frame_(frame ? std::move(*frame) : TrackingFrame(width_, height_, bin_shift_, std::move(undistortion))),
      fit_subpixel_(config.subpixel_method == "template_fit"),
      neighbour_model_(config.neighbour_motion_model == "similarity" ? NeighbourModel::kSimilarity
                       : config.neighbour_motion_model == "either"   ? NeighbourModel::kEither
                                                                     : NeighbourModel::kTranslation),
      similarity_min_px_(static_cast<float>(config.neighbour_similarity_min_px)),
      similarity_agreement_px_(static_cast<float>(config.neighbour_similarity_agreement_px)),
      sae_(width_, height_, msToNs(config.refractory_period_ms)),
      detector_(sae_, detectorParams(config)),
      registration_(static_cast<std::size_t>(frame_.gridWidth()) * frame_.gridHeight(), -1),
      pixel_events_(static_cast<std::size_t>(width_) * height_, 0),
      slots_(config.max_features),
      id_map_(config.max_features),
      grid_w_((frame_.gridWidth() + (1 << kCellShift) - 1) >> kCellShift),
      grid_h_((frame_.gridHeight() + (1 << kCellShift) - 1) >> kCellShift),
      cell_heads_(static_cast<std::size_t>(grid_w_) * grid_h_, -1),
      max_reversal_ns_(std::llround(config.max_time_reversal_us * 1e3)),
      min_dt_ns_(msToNs(config.min_dt_ms)),
      max_idle_ns_(msToNs(config.max_idle_ms)),
      init_timeout_ns_(msToNs(config.init_timeout_ms)),
      init_timeout_max_ns_(msToNs(config.init_timeout_max_ms)),
      housekeeping_ns_(std::max<int64_t>(1, msToNs(config.housekeeping_ms))),
      drift_check_ns_(std::max<int64_t>(1, msToNs(config.drift_check_ms))),
      neighbour_check_ns_(std::max<int64_t>(1, msToNs(config.neighbour_check_ms))),
      neighbour_window_ns_(std::max<int64_t>(1, msToNs(config.neighbour_window_ms))),
      max_rotation_rad_(static_cast<float>(config.max_rotation_deg * kPi / 180.0)),
      border_margin_(static_cast<float>(config.border_margin_px)),
      min_distance_px_(config.min_distance_px * config.distanceScale(width_, height_)),
      neighbour_radius_px_(config.neighbour_radius_px * config.distanceScale(width_, height_)) {
  config.validate();
  stats_.harris_threshold = stats_.min_harris_threshold = config.harris_threshold;
  if (config.hot_pixel_filter)
    hot_pixel_filter_ = std::make_unique<HotPixelFilter>(width_, height_, msToNs(config.hot_pixel_window_ms),
                                                         config.hot_pixel_factor, config.hot_pixel_min_rate_hz);
  if (config.noise_filter)
    noise_filter_ = std::make_unique<BackgroundActivityFilter>(width_, height_, msToNs(config.noise_filter_ms));
  if (config.max_event_rate_mev_s > 0)
    rate_budget_ = std::make_unique<EventRateBudget>(config.max_event_rate_mev_s * 1e6, kRateWindowNs);
  if (undistortion.width() != 0 && (undistortion.width() != width || undistortion.height() != height))
    throw Error(fmt::format("frontend: undistortion table is {}x{} but the sensor is {}x{}",
                            undistortion.width(), undistortion.height(), width, height));
  const HasteParams haste = hasteParams(config);
  free_slots_.reserve(slots_.size());
  for (int i = static_cast<int>(slots_.size()) - 1; i >= 0; --i) {
    slots_[i].tracker = makeHasteTracker(haste);
    if (config.max_neighbour_disagreement_px > 0) slots_[i].history.resize(kHistoryCapacity);
    free_slots_.push_back(i);
  }
  changed_.reserve(slots_.size());
  roll_scratch_.resize(slots_.size());
  if (config.max_neighbour_disagreement_px > 0) {
    candidates_.reserve(slots_.size());
    neighbour_d2_.reserve(slots_.size());
    neighbour_dx_.reserve(slots_.size());
    neighbour_dy_.reserve(slots_.size());
    neighbour_ax_.reserve(slots_.size());
    neighbour_ay_.reserve(slots_.size());
    median_x_.reserve(slots_.size());
    median_y_.reserve(slots_.size());
    const auto pairs = static_cast<std::size_t>(config.neighbour_count * (config.neighbour_count - 1) / 2);
    pair_angle_.reserve(pairs);
    pair_log_scale_.reserve(pairs);
    neighbour_drops_.reserve(slots_.size());
  }
}

Frontend::~Frontend() = default;

void Frontend::cellInsert(int slot, int cell) {
  assert(cell >= 0 && cell < static_cast<int>(cell_heads_.size()));
  slots_[slot].cell = cell;
  slots_[slot].next_in_cell = cell_heads_[cell];
  cell_heads_[cell] = slot;
}

void Frontend::cellRemove(int slot) {
  const int cell = slots_[slot].cell;
  if (cell < 0) return;
  int* link = &cell_heads_[cell];
  while (*link != slot) {
    assert(*link >= 0);
    link = &slots_[*link].next_in_cell;
  }
  *link = slots_[slot].next_in_cell;
  slots_[slot].cell = -1;
  slots_[slot].next_in_cell = -1;
}

void Frontend::process(const Event& raw, MeasurementSink& sink) {
  ++stats_.events;
  if (raw.x >= sensor_width_ || raw.y >= sensor_height_) {
    ++stats_.dropped_out_of_sensor;
    return;
  }
  Event input = raw;
  input.x = static_cast<uint16_t>(raw.x >> bin_shift_);
  input.y = static_cast<uint16_t>(raw.y >> bin_shift_);
  int64_t t = input.t_ns;
  if (!started_) {
    started_ = true;
    stats_.first_t_ns = t;
    newest_t_ns_ = t;
    last_housekeeping_ns_ = t;
    next_housekeeping_ns_ = t + housekeeping_ns_;
    next_neighbour_check_ns_ = t + neighbour_check_ns_;
  } else if (t < newest_t_ns_) {
    if (newest_t_ns_ - t > max_reversal_ns_) {
      ++stats_.dropped_time_reversal;
      return;
    }
    ++stats_.clamped_time;
    t = newest_t_ns_;
  }
  newest_t_ns_ = t;
  stats_.last_t_ns = t;
  uint32_t& pixel_count = pixel_events_[static_cast<std::size_t>(input.y) * width_ + input.x];
  pixel_count += pixel_count != UINT32_MAX ? 1 : 0;
  if (t >= next_housekeeping_ns_) housekeeping(t, sink);
  if (hot_pixel_filter_ && !hot_pixel_filter_->pass(input.x, input.y, t)) {
    ++stats_.dropped_hot_pixel;
    return;
  }
  if (noise_filter_ && !noise_filter_->pass(input.x, input.y, t)) {
    ++stats_.dropped_noise_filter;
    return;
  }
  const EventRateBudget::Decision budget = rate_budget_ ? rate_budget_->admit(t) : EventRateBudget::Decision::kFull;
  if (budget == EventRateBudget::Decision::kShed) {
    ++stats_.events_shed;
    return;
  }

  Event e = input;
  e.t_ns = t;
  const bool accepted = sae_.update(e);
  stats_.filter_accepted += accepted ? 1 : 0;

  // Dispatch to the trackers of the 3x3 cells around the event's tracking-frame position.
  float ex, ey;
  if (!frame_.position(e.x, e.y, ex, ey)) {
    ++stats_.events_without_position;
    return;
  }
  const int cx = static_cast<int>(ex - frame_.originX()) >> kCellShift;
  const int cy = static_cast<int>(ey - frame_.originY()) >> kCellShift;
  const int gx0 = std::max(cx - 1, 0), gx1 = std::min(cx + 1, grid_w_ - 1);
  const int gy0 = std::max(cy - 1, 0), gy1 = std::min(cy + 1, grid_h_ - 1);
  bool used = false;
  changed_.clear();
  for (int gy = gy0; gy <= gy1; ++gy) {
    for (int gx = gx0; gx <= gx1; ++gx) {
      for (int s = cell_heads_[gy * grid_w_ + gx]; s >= 0; s = slots_[s].next_in_cell) {
        Slot& slot = slots_[s];
        // HasteTracker::push's range test, on the slot's copy of the tracker position.
        const float dx = ex - slot.x, dy = ey - slot.y;
        if (!(dx * dx + dy * dy < float(HasteTracker::kRadius * HasteTracker::kRadius))) continue;
        HasteTracker& tracker = *slot.tracker;
        const TrackerResult r = tracker.pushInRange(t, ex, ey);
        used = true;
        ++stats_.tracker_updates;
        slot.x = tracker.state().x;
        slot.y = tracker.state().y;
        if (r == TrackerResult::kStateChanged || !tracker.healthy()) changed_.emplace_back(s, slot.id);
      }
    }
  }
  for (const auto& [slot, id] : changed_)
    if (slots_[slot].id == id) onStateChange(slot, t, sink);  // may have been dropped by a collision

  if (used || stats_.active_features >= config_.max_features) return;
  if (budget == EventRateBudget::Decision::kTrackOnly) {
    ++stats_.detections_skipped;
    return;
  }
  ++stats_.detector_runs;
  const CornerResult corner = detector_.detect(e, accepted);
  stats_.candidates += corner.candidate ? 1 : 0;
  if (!corner.corner) return;
  ++stats_.corners;
  trySeed(e, ex, ey);
}

void Frontend::onStateChange(int slot, int64_t t_ns, MeasurementSink& sink) {
  Slot& s = slots_[slot];
  const HasteTracker& tracker = *s.tracker;
  if (!tracker.healthy()) return drop(slot, DropReason::kUnhealthy, t_ns, sink);
  ++stats_.state_changes;
  const TrackerState& st = tracker.state();
  if (!frame_.inside(st.x, st.y, border_margin_)) return drop(slot, DropReason::kBorder, t_ns, sink);
  s.last_change_ns = t_ns;
  s.scene_changes_at_last_change = stats_.state_changes;
  if (!s.history.empty()) {  // neighbour-motion test enabled: remember the state
    const int cap = static_cast<int>(s.history.size());
    int index;
    if (s.history_size < cap) {
      index = (s.history_head + s.history_size++) % cap;
    } else {
      index = s.history_head;
      s.history_head = (s.history_head + 1) % cap;
    }
    s.history[static_cast<std::size_t>(index)] = PositionSample{st.t_ns, st.x, st.y};
  }
  if (tracker.stateChanges() == 1) {  // initialization: the template's frame starts at the common roll
    s.roll_at_init = common_roll_;
    s.next_drift_check_ns = t_ns + drift_check_ns_;
  }

  // Registration table: collisions with another feature within the collision radius.
  const int grid_w = frame_.gridWidth(), grid_h = frame_.gridHeight();
  int rx, ry;
  frame_.gridCell(st.x, st.y, rx, ry);
  const int reg = ry * grid_w + rx;
  if (reg != s.reg_index) {
    if (s.reg_index >= 0 && registration_[s.reg_index] == s.id) registration_[s.reg_index] = -1;
    s.reg_index = -1;
    const float radius = static_cast<float>(config_.collision_radius_px);
    const int r = static_cast<int>(std::ceil(radius));
    for (int y = std::max(ry - r, 0); y <= std::min(ry + r, grid_h - 1); ++y) {
      for (int x = std::max(rx - r, 0); x <= std::min(rx + r, grid_w - 1); ++x) {
        const int64_t other = registration_[static_cast<std::size_t>(y) * grid_w + x];
        if (other < 0 || other == s.id) continue;
        const int other_slot = id_map_.find(other);
        assert(other_slot >= 0);
        const TrackerState& os = slots_[other_slot].tracker->state();
        const float dx = os.x - st.x, dy = os.y - st.y;
        if (dx * dx + dy * dy > radius * radius && !(x == rx && y == ry)) continue;
        if (other < s.id) return drop(slot, DropReason::kCollision, t_ns, sink);  // the older one stays
        drop(other_slot, DropReason::kCollision, t_ns, sink);
      }
    }
    registration_[reg] = s.id;
    s.reg_index = reg;
  }
  const int cell = cellOf(rx, ry);
  if (cell != s.cell) {
    cellRemove(slot);
    cellInsert(slot, cell);
  }

  // Measurement, at most one per min_dt of state time.
  if (s.recorded && st.t_ns - s.last_recorded_ns < min_dt_ns_) return;
  TrackMeasurement m;
  m.feature_id = s.id;
  m.t_ns = st.t_ns;
  float x = st.x, y = st.y;
  if (config_.subpixel_measurements) {
    float dx = 0.f, dy = 0.f;
    if (!fit_subpixel_) {
      tracker.subpixelOffset(dx, dy);
    } else if (!tracker.subpixelFit(dx, dy)) {
      ++stats_.subpixel_fit_failures;
      tracker.subpixelOffset(dx, dy);
    }
    x += dx;
    y += dy;
  }
  if (!frame_.measurement(x, y, m.x, m.y, m.xn, m.yn)) {
    ++stats_.measurements_without_undistortion;
    return;
  }
  s.recorded = true;
  s.last_recorded_ns = st.t_ns;
  ++s.measurements;
  ++stats_.measurements;
  sink.onMeasurement(m);
}

void Frontend::trySeed(const Event& e, float x, float y) {
  // The border is the sensor's, at the event's pixel.
  if (!TrackingFrame::withinMargin(float(e.x), float(e.y), width_, height_, border_margin_)) return;
  // Patch search: no registered feature within min_distance (on the tracking frame's grid).
  const int grid_w = frame_.gridWidth(), grid_h = frame_.gridHeight();
  int gx, gy;
  frame_.gridCell(x, y, gx, gy);
  const double d = min_distance_px_;
  const int r = static_cast<int>(std::floor(d));
  for (int yy = std::max(gy - r, 0); yy <= std::min(gy + r, grid_h - 1); ++yy) {
    const int64_t* row = &registration_[static_cast<std::size_t>(yy) * grid_w];
    const int dy = yy - gy;
    for (int xx = std::max(gx - r, 0); xx <= std::min(gx + r, grid_w - 1); ++xx) {
      const int dx = xx - gx;
      if (row[xx] >= 0 && dx * dx + dy * dy <= d * d) return;
    }
  }
  if (free_slots_.empty()) return;
  const int slot = free_slots_.back();
  free_slots_.pop_back();
  Slot& s = slots_[slot];
  s.id = next_id_++;
  s.created_ns = e.t_ns;
  s.last_change_ns = e.t_ns;
  s.scene_changes_at_last_change = stats_.state_changes;
  s.recorded = false;
  s.measurements = 0;
  s.history_head = 0;
  s.history_size = 0;
  s.tracker->reset(e.t_ns, x, y);
  s.tracker->push(e.t_ns, x, y);  // the seed event is the first of its window
  s.x = s.tracker->state().x;
  s.y = s.tracker->state().y;
  s.reg_index = gy * grid_w + gx;
  registration_[s.reg_index] = s.id;
  id_map_.insert(s.id, slot);
  cellInsert(slot, cellOf(gx, gy));
  ++stats_.features_created;
  ++stats_.active_features;
  stats_.max_active_features = std::max(stats_.max_active_features, stats_.active_features);
}

void Frontend::drop(int slot, DropReason reason, int64_t t_ns, MeasurementSink& sink) {
  Slot& s = slots_[slot];
  assert(s.id >= 0);
  if (s.reg_index >= 0 && registration_[s.reg_index] == s.id) registration_[s.reg_index] = -1;
  s.reg_index = -1;
  cellRemove(slot);
  id_map_.erase(s.id);
  ++stats_.features_dropped[static_cast<int>(reason)];
  --stats_.active_features;
  sink.onFeatureEnd(FeatureEnd{s.id, t_ns, reason, s.measurements});
  s.id = -1;
  free_slots_.push_back(slot);
}

float Frontend::rollDeparture(const Slot& s) const {
  return wrapAngle(s.tracker->state().theta + s.roll_at_init - common_roll_);
}

void Frontend::updateCommonRoll() {
  // The in-plane rotation every patch of a rigid scene undergoes is (to first order) the camera's roll
  // about its optical axis: estimate it robustly as the median over the initialized features of their
  // rotation since initialization plus the common roll at that time (relative to the current estimate,
  // so the median is taken away from the wrap-around).
  int n = 0;
  for (const Slot& s : slots_)
    if (s.id >= 0 && s.tracker->initialized())
      roll_scratch_[static_cast<std::size_t>(n++)] = rollDeparture(s);
  if (n < 3) return;  // too few features for a robust common value
  const auto mid = roll_scratch_.begin() + n / 2;
  std::nth_element(roll_scratch_.begin(), mid, roll_scratch_.begin() + n);
  common_roll_ = wrapAngle(common_roll_ + *mid);
}

void Frontend::adaptDetectionThreshold(int64_t t_ns) {
  constexpr int64_t kStepNs = 10'000'000;
  constexpr double kFactor = 0.95;
  next_threshold_update_ns_ = t_ns + kStepNs;
  const double base = config_.harris_threshold;
  const double floor = base * config_.harris_threshold_floor;
  double& threshold = stats_.harris_threshold;
  // Harris scores are positive for corners; a non-positive base threshold has nothing to relax.
  if (!(base > 0)) return;
  if (4 * stats_.active_features < 3 * config_.max_features) {
    threshold = std::max(floor, threshold * kFactor);
  } else if (10 * stats_.active_features >= 9 * config_.max_features) {
    threshold = std::min(base, threshold / kFactor);
  } else {
    return;
  }
  detector_.setHarrisThreshold(threshold);
  stats_.min_harris_threshold = std::min(stats_.min_harris_threshold, threshold);
}

void Frontend::housekeeping(int64_t t_ns, MeasurementSink& sink) {
  const double since_last_s = durationSeconds(last_housekeeping_ns_, t_ns);
  stats_.active_feature_seconds += stats_.active_features * since_last_s;
  const auto count = static_cast<std::size_t>(stats_.active_features);
  if (count >= stats_.seconds_at_active_count.size()) stats_.seconds_at_active_count.resize(count + 1, 0.0);
  stats_.seconds_at_active_count[count] += since_last_s;
  last_housekeeping_ns_ = t_ns;
  next_housekeeping_ns_ = t_ns + housekeeping_ns_;
  if (config_.harris_threshold_floor < 1.0 && t_ns >= next_threshold_update_ns_) adaptDetectionThreshold(t_ns);
  if (max_rotation_rad_ > 0) updateCommonRoll();
  int tracking = 0;  // initialized features: the ones whose state changes measure the scene's motion
  if (config_.init_timeout_scene_px > 0)
    for (const Slot& s : slots_) tracking += s.id >= 0 && s.tracker->initialized() ? 1 : 0;
  for (int slot = 0; slot < static_cast<int>(slots_.size()); ++slot) {
    Slot& s = slots_[slot];
    if (s.id < 0) continue;
    HasteTracker& tracker = *s.tracker;
    if (!tracker.initialized()) {
      // Waiting for its first window: past init_timeout_ms, and (with init_timeout_scene_px) once the
      // scene moved that far since its creation (its corner has moved on without it) or past
      // init_timeout_max_ms. A tracker has no state change before its window fills, so
      // scene_changes_at_last_change still holds the count at its creation.
      const int64_t age = t_ns - s.created_ns;
      if (age > init_timeout_ns_ &&
          (config_.init_timeout_scene_px <= 0 || age > init_timeout_max_ns_ ||
           sceneMovedSince(s.scene_changes_at_last_change, config_.init_timeout_scene_px, tracking)))
        drop(slot, DropReason::kInitTimeout, t_ns, sink);
    } else if (t_ns - s.last_change_ns > max_idle_ns_ &&
               sceneMovedSince(s.scene_changes_at_last_change, config_.idle_min_scene_motion_px,
                               stats_.active_features)) {
      // Idle while the scene moved on: its corner is gone. A camera at rest (or reversing) moves no
      // tracker, and its features are kept.
      drop(slot, DropReason::kIdle, t_ns, sink);
    } else if (tracker.windowAnisotropy() < config_.min_anisotropy) {
      drop(slot, DropReason::kQuality, t_ns, sink);
    } else if (max_rotation_rad_ > 0 && std::abs(rollDeparture(s)) > max_rotation_rad_) {
      drop(slot, DropReason::kRotation, t_ns, sink);
    } else if (config_.max_drift_px > 0 && t_ns >= s.next_drift_check_ns) {
      s.next_drift_check_ns = t_ns + drift_check_ns_;
      if (tracker.firstTemplateDrift() > config_.max_drift_px) drop(slot, DropReason::kDrift, t_ns, sink);
    }
  }
  if (config_.max_neighbour_disagreement_px > 0 && t_ns >= next_neighbour_check_ns_) {
    next_neighbour_check_ns_ = t_ns + neighbour_check_ns_;
    neighbourCheck(t_ns, sink);
  }
}

bool Frontend::sceneMovedSince(uint64_t changes_at, double px, int features) const {
  return static_cast<double>(stats_.state_changes - changes_at) >= px * std::max(features, 1);
}

bool Frontend::positionAt(const Slot& s, int64_t t_ns, float& x, float& y) const {
  const int cap = static_cast<int>(s.history.size());
  if (s.history_size == 0) return false;
  auto at = [&](int i) -> const PositionSample& {
    return s.history[static_cast<std::size_t>((s.history_head + i) % cap)];
  };
  if (at(0).t_ns > t_ns) return false;  // not tracked (or not remembered) that far back
  // Newest sample at or before t (state times of one feature never decrease).
  int i = s.history_size - 1;
  while (at(i).t_ns > t_ns) --i;
  const PositionSample& a = at(i);
  if (i == s.history_size - 1) {  // no state change since: still there
    x = a.x;
    y = a.y;
    return true;
  }
  const PositionSample& b = at(i + 1);
  // The state moves in 1-px steps at its state changes; between two changes the feature moved
  // steadily from one to the next, so interpolate linearly (the half-step offset this implies is the same
  // at both ends of a displacement and cancels).
  const float w =
      b.t_ns > a.t_ns ? static_cast<float>(t_ns - a.t_ns) / static_cast<float>(b.t_ns - a.t_ns) : 1.f;
  x = a.x + w * (b.x - a.x);
  y = a.y + w * (b.y - a.y);
  return true;
}

float Frontend::carryToFeature(float xa, float ya) {
  // Under an image similarity p -> z p + t (complex z = scale x e^{i angle}) the displacement is
  // d(p) = (z - 1) p + t, so a neighbour n predicts the feature's displacement as
  // d_n + (z - 1)(p_f - p_n), whatever the centre of the rotation. z is the median angle and median log
  // scale of the neighbour pairs (each pair's vector at t_a against the same at t_b), robust to a
  // minority of bad neighbours as the median displacement is. A roll or a zoom, which moves neighbours
  // apart in proportion to their distance, then no longer parts them.
  constexpr float kMinPairPx = 4.f;  // a shorter pair's angle is too noisy
  const std::size_t m = neighbour_dx_.size();
  pair_angle_.clear();
  pair_log_scale_.clear();
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 1; b < m; ++b) {
      const float ux = neighbour_ax_[b] - neighbour_ax_[a], uy = neighbour_ay_[b] - neighbour_ay_[a];
      const float vx = ux + neighbour_dx_[b] - neighbour_dx_[a], vy = uy + neighbour_dy_[b] - neighbour_dy_[a];
      const float u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
      if (u2 < kMinPairPx * kMinPairPx || v2 < kMinPairPx * kMinPairPx) continue;
      pair_angle_.push_back(std::atan2(ux * vy - uy * vx, ux * vx + uy * vy));
      pair_log_scale_.push_back(0.5f * std::log(v2 / u2));
    }
  if (pair_angle_.size() < 3) return 0.f;  // the translation model
  const float angle = median(pair_angle_), scale = std::exp(median(pair_log_scale_));
  const float zr = scale * std::cos(angle) - 1.f, zi = scale * std::sin(angle);  // z - 1
  float cx = 0.f, cy = 0.f;
  for (std::size_t n = 0; n < m; ++n) {
    const float wx = xa - neighbour_ax_[n], wy = ya - neighbour_ay_[n];
    neighbour_dx_[n] += zr * wx - zi * wy;
    neighbour_dy_[n] += zi * wx + zr * wy;
    cx += wx;
    cy += wy;
  }
  return std::sqrt(zr * zr + zi * zi) * std::hypot(cx, cy) / static_cast<float>(m);
}

void Frontend::neighbourCheck(int64_t t_ns, MeasurementSink& sink) {
  // Neighbour-motion consistency (docs/method/frontend_quality.md). Nearby points of a scene move
  // alike in the image (the motion field is smooth away from depth discontinuities), while a tracker
  // creeping around a soft blob, lagging behind a fast motion or jumping to a similar structure does not
  // follow its neighbours. Each initialized feature's displacement over [t_a, t_b], t_b = now - lag,
  // t_a = max(t_b - window, its first state), is compared with the component-wise median displacement of
  // its k nearest features over the same interval (features within a radius that were tracked at t_a).
  // The median makes the reference robust to a minority of bad neighbours, as in the Median Flow tracker
  // (Kalal, Mikolajczyk, Matas, "Forward-backward error: automatic detection of tracking failures", ICPR
  // 2010). All residuals are computed before any drop.
  const int64_t tb = t_ns - kNeighbourLagNs;
  candidates_.clear();
  for (int slot = 0; slot < static_cast<int>(slots_.size()); ++slot) {
    const Slot& s = slots_[slot];
    if (s.id < 0 || !s.tracker->initialized() || s.history_size == 0) continue;
    const int64_t first = s.history[static_cast<std::size_t>(s.history_head)].t_ns;
    if (first > tb - kNeighbourMinSpanNs) continue;
    const TrackerState& st = s.tracker->state();
    candidates_.push_back(Candidate{slot, st.x, st.y, first});
  }
  const int n = static_cast<int>(candidates_.size());
  if (n < 4) return;
  const float radius2 = static_cast<float>(neighbour_radius_px_ * neighbour_radius_px_);
  const float limit = static_cast<float>(config_.max_neighbour_disagreement_px);
  const float fraction = static_cast<float>(config_.neighbour_disagreement_fraction);
  neighbour_drops_.clear();
  for (int i = 0; i < n; ++i) {
    const Candidate& c = candidates_[static_cast<std::size_t>(i)];
    const int64_t ta = std::max(tb - neighbour_window_ns_, c.first_ns);
    neighbour_d2_.clear();
    for (int j = 0; j < n; ++j) {
      const Candidate& o = candidates_[static_cast<std::size_t>(j)];
      if (j == i || o.first_ns > ta) continue;
      const float d2 = (o.x - c.x) * (o.x - c.x) + (o.y - c.y) * (o.y - c.y);
      if (d2 <= radius2) neighbour_d2_.emplace_back(d2, j);
    }
    if (neighbour_d2_.size() < 3) continue;  // too few neighbours for a robust reference
    const std::size_t k =
        std::min<std::size_t>(neighbour_d2_.size(), static_cast<std::size_t>(config_.neighbour_count));
    std::nth_element(neighbour_d2_.begin(), neighbour_d2_.begin() + static_cast<std::ptrdiff_t>(k - 1),
                     neighbour_d2_.end());
    float xa, ya, xb, yb;
    neighbour_dx_.clear();
    neighbour_dy_.clear();
    neighbour_ax_.clear();
    neighbour_ay_.clear();
    for (std::size_t m = 0; m < k; ++m) {
      const Slot& o = slots_[static_cast<std::size_t>(
          candidates_[static_cast<std::size_t>(neighbour_d2_[m].second)].slot)];
      if (!positionAt(o, ta, xa, ya) || !positionAt(o, tb, xb, yb)) continue;
      neighbour_dx_.push_back(xb - xa);
      neighbour_dy_.push_back(yb - ya);
      neighbour_ax_.push_back(xa);
      neighbour_ay_.push_back(ya);
    }
    const Slot& s = slots_[static_cast<std::size_t>(c.slot)];
    if (neighbour_dx_.size() < 3 || !positionAt(s, ta, xa, ya) || !positionAt(s, tb, xb, yb)) continue;
    ++stats_.neighbour_tests;
    // The reference: the component-wise median of the neighbours' (carried) displacements, taken from
    // copies (the medians reorder their inputs).
    auto reference = [&]() {
      median_x_.assign(neighbour_dx_.begin(), neighbour_dx_.end());
      median_y_.assign(neighbour_dy_.begin(), neighbour_dy_.end());
      return std::pair<float, float>(median(median_x_), median(median_y_));
    };
    auto disagrees = [&](const std::pair<float, float>& m) {
      const float ex = (xb - xa) - m.first, ey = (yb - ya) - m.second;
      const float bound = limit + fraction * std::sqrt(m.first * m.first + m.second * m.second);
      return ex * ex + ey * ey > bound * bound;
    };
    // Whether a neighbour's (carried) displacement lies farther than `bound` from the reference m.
    auto anyNeighbourBeyond = [&](const std::pair<float, float>& m, float bound) {
      for (std::size_t j = 0; j < neighbour_dx_.size(); ++j) {
        const float ex = neighbour_dx_[j] - m.first, ey = neighbour_dy_[j] - m.second;
        if (ex * ex + ey * ey > bound * bound) return true;
      }
      return false;
    };
    bool drop_it = neighbour_model_ == NeighbourModel::kSimilarity || disagrees(reference());
    if (drop_it && neighbour_model_ != NeighbourModel::kTranslation) {
      const float correction = carryToFeature(xa, ya);
      const bool either = neighbour_model_ == NeighbourModel::kEither;
      // either: a similarity that hardly moves the feature relative to its neighbours is noise, and the
      // translation's verdict (drop) stands; with an agreement bound, so does one the neighbours themselves
      // do not follow (neighbours on two motions, across a depth discontinuity).
      if (!either || correction >= similarity_min_px_) {
        const std::pair<float, float> carried = reference();
        drop_it = disagrees(carried) ||
                  (either && similarity_agreement_px_ > 0.f && anyNeighbourBeyond(carried, similarity_agreement_px_));
      }
    }
    if (drop_it) neighbour_drops_.push_back(c.slot);
  }
  for (int slot : neighbour_drops_) drop(slot, DropReason::kNeighbour, t_ns, sink);
}

void Frontend::finish(MeasurementSink& sink) {
  if (started_) housekeeping(newest_t_ns_, sink);
  for (int slot = 0; slot < static_cast<int>(slots_.size()); ++slot)
    if (slots_[slot].id >= 0) drop(slot, DropReason::kFinished, newest_t_ns_, sink);
}

std::vector<std::pair<int, int>> Frontend::hotPixels() const {
  std::vector<std::pair<int, int>> pixels =
      hot_pixel_filter_ ? hot_pixel_filter_->hotPixels() : std::vector<std::pair<int, int>>{};
  for (auto& [x, y] : pixels) {  // a bin's first sensor pixel
    x <<= bin_shift_;
    y <<= bin_shift_;
  }
  return pixels;
}

std::vector<Frontend::PixelCount> Frontend::dominantPixels(double share, int max_pixels) const {
  uint64_t total = 0;
  for (uint32_t c : pixel_events_) total += c;
  std::vector<PixelCount> top;
  if (total == 0 || max_pixels <= 0) return top;
  // Keep the max_pixels busiest pixels (a min-heap on the count would do; max_pixels is small).
  for (std::size_t i = 0; i < pixel_events_.size(); ++i) {
    const uint32_t c = pixel_events_[i];
    if (c == 0 || (static_cast<int>(top.size()) == max_pixels && c <= top.back().events)) continue;
    PixelCount p{static_cast<int>(i % static_cast<std::size_t>(width_)), static_cast<int>(i / static_cast<std::size_t>(width_)), c};
    auto at = std::upper_bound(top.begin(), top.end(), p,
                               [](const PixelCount& a, const PixelCount& b) { return a.events > b.events; });
    top.insert(at, p);
    if (static_cast<int>(top.size()) > max_pixels) top.pop_back();
  }
  for (PixelCount& p : top) {  // a bin's first sensor pixel
    p.x <<= bin_shift_;
    p.y <<= bin_shift_;
  }
  uint64_t sum = 0;
  for (std::size_t k = 0; k < top.size(); ++k) {
    sum += top[k].events;
    if (static_cast<double>(sum) > share * static_cast<double>(total)) {
      top.resize(k + 1);
      return top;
    }
  }
  return {};
}

std::vector<Frontend::FeatureView> Frontend::features() const {
  std::vector<FeatureView> out;
  for (const Slot& s : slots_)
    if (s.id >= 0) out.push_back(FeatureView{s.id, s.tracker->state(), s.tracker->initialized()});
  std::sort(out.begin(), out.end(), [](const FeatureView& a, const FeatureView& b) { return a.id < b.id; });
  return out;
}

}  // namespace asynevo::frontend
