#include "asynevo/backend/sliding_window_estimator.hpp"

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <string_view>
#include <tuple>
#include <utility>
#include <cmath>
#include <limits>

#include "asynevo/backend/factors/fixed_pose_projection_factor.hpp"
#include "asynevo/backend/factors/gp_projection_factor.hpp"
#include "asynevo/backend/factors/scale_anchor_factor.hpp"
#include "asynevo/backend/factors/se3_manifold.hpp"
#include "asynevo/backend/factors/state_prior_factor.hpp"
#include "asynevo/backend/factors/wnoa_prior_factor.hpp"
#include "asynevo/backend/direction_audit.hpp"
#include "asynevo/backend/initializer.hpp"
#include "asynevo/backend/landmark_rejoin.hpp"
#include "asynevo/backend/multiview_initializer.hpp"
#include "asynevo/backend/start_trajectory.hpp"
#include "asynevo/backend/marginalization.hpp"
#include "asynevo/backend/triangulation.hpp"
#include "asynevo/backend/window_solver.hpp"
#include "asynevo/core/time.hpp"
#include "upper_median.hpp"

namespace asynevo::backend {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

bool finiteKnot(const Knot& knot) {
  return std::all_of(knot.pose.begin(), knot.pose.end(), [](double v) { return std::isfinite(v); }) &&
         std::all_of(knot.velocity.begin(), knot.velocity.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& options)
    : options_(options),
      knot_dt_ns_(std::llround(options.config.knot_dt_ms * 1e6)),
      measurement_dt_ns_(std::llround(options.config.track_measurement_dt_ms * 1e6)),
      se3_manifold_(std::make_unique<SE3Manifold>()),
      solver_workspace_(std::make_unique<WindowSolverWorkspace>()),
      final_velocity_(std::max(options.config.linear_velocity_span_knots, 0)) {
  options_.config.validate();
  triangulation_views_ = triangulationViewsFromName(options_.config.triangulation_views);
  if (options_.config.pixel_bounds_focal_px > 0) {  // the bounds are angles above the reference focal length
    BackendConfig& c = options_.config;
    const double scale = std::max(1.0, options_.focal_px / c.pixel_bounds_focal_px);
    for (double* px : {&c.huber_px, &c.outlier_px, &c.track_outlier_rms_px, &c.track_split_px,
                       &c.max_triangulation_px, &c.loss_max_median_px})
      *px *= scale;
  }
  huber_ = std::make_shared<ceres::HuberLoss>(options_.config.huber_px / options_.config.pixel_sigma);
  Q_c_.setZero();
  for (int i = 0; i < 6; ++i) Q_c_(i, i) = options_.config.q_c[static_cast<std::size_t>(i)];
}

SlidingWindowEstimator::~SlidingWindowEstimator() = default;

void SlidingWindowEstimator::addMeasurement(const TrackMeasurement& m) {
  ++stats_.measurements_received;
  if (!std::isfinite(m.xn) || !std::isfinite(m.yn)) {
    ++stats_.measurements_non_finite;
    return;
  }
  if (m.t_ns < reset_ns_) {
    ++stats_.measurements_before_reset;
    return;
  }
  if (superseded_features_.count(m.feature_id)) {
    ++stats_.measurements_of_superseded_features;
    return;
  }
  const auto alias = split_aliases_.find(m.feature_id);
  const int64_t key = alias == split_aliases_.end() ? m.feature_id : alias->second;
  if (rejected_features_.count(key)) {
    ++stats_.measurements_of_rejected_tracks;
    return;
  }
  if (tracking_ && m.t_ns < trajectory_.oldestTime()) {
    ++stats_.measurements_before_window;
    return;
  }
  FeatureTrack& track = tracks_[key];
  track.id = key;
  if (!track.observations.empty() && m.t_ns < track.lastTime()) {
    ++stats_.measurements_out_of_order;
    return;
  }
  if (!track.observations.empty() && m.t_ns - track.lastTime() < measurement_dt_ns_) {
    ++stats_.measurements_subsampled;
    return;
  }
  Eigen::Vector2d xn(m.xn, m.yn);
  if (const auto offset = rejoin_offsets_.find(m.feature_id); offset != rejoin_offsets_.end()) xn -= offset->second;
  track.observations.push_back({m.t_ns, xn});
  if (first_measurement_ns_ < 0) first_measurement_ns_ = m.t_ns;
}

// Alg. 1's "ended before t_eps" is read from the last measurement time (marginalizeDynamic): a feature
// that stays quiet is marked like an ended one, and a later measurement of it starts a new trajectory.
void SlidingWindowEstimator::endFeature(int64_t feature_id) {
  // An ended feature sends no more measurements: what was kept to route or ignore them is forgotten,
  // so these sets stay as small as the active features over a run of any length.
  const auto alias = split_aliases_.find(feature_id);
  const int64_t key = alias == split_aliases_.end() ? feature_id : alias->second;
  if (alias != split_aliases_.end()) {
    rejected_features_.erase(alias->second);
    split_aliases_.erase(alias);
  }
  rejected_features_.erase(feature_id);
  superseded_features_.erase(feature_id);
  rejoin_offsets_.erase(feature_id);
  const auto track = tracks_.find(key);
  if (track != tracks_.end()) track->second.feature_ended = true;
}

void SlidingWindowEstimator::advanceTo(int64_t t_ns) {
  // A gap in the events: nothing constrains the motion across it, so the segment ends at the last
  // event before it and the estimator starts again with what comes after it.
  const double gap_ms = options_.config.loss_max_event_gap_ms;
  if (gap_ms > 0 && last_event_ns_ > 0 && durationSeconds(last_event_ns_, t_ns) * 1e3 > gap_ms) {
    // Measurements are forgotten up to the middle of the gap: a tracker can stamp a measurement after
    // the last marker before the gap and deliver it only after the gap, and such a measurement would
    // let a start interpolate its track across the gap (its first knots would then lie inside it).
    const int64_t reset_ns = last_event_ns_ + (t_ns - last_event_ns_) / 2;
    if (tracking_) {
      loseTracking(SegmentEnd::kEventGap, t_ns, last_event_ns_, reset_ns);
    } else {  // measurements from before the gap would pair with ones after it in a two-view start
      restartInitialization(reset_ns);
    }
  }
  last_event_ns_ = std::max(last_event_ns_, t_ns);
  if (!tracking_) {
    const bool due = !last_init_attempt_ns_ || t_ns - *last_init_attempt_ns_ >= knot_dt_ns_;
    if (first_measurement_ns_ >= 0 && due) tryInitialize(t_ns);
    return;
  }
  const int per_update = options_.config.knots_per_update;
  while (tracking_ && t_ns >= trajectory_.newestTime() + per_update * knot_dt_ns_) {
    for (int k = 0; k < per_update; ++k) {
      trajectory_.extendTo(trajectory_.newestTime() + knot_dt_ns_);
      ++stats_.knots;
    }
    update(t_ns);
  }
}

InitResult SlidingWindowEstimator::findInitialMotion(int64_t earliest_ns, int64_t t_b_ns, const BackendConfig& config,
                                                     bool relaxed_counts) const {
  const std::string& method = config.init_method;
  InitResult two_view;
  if (method != "multi-view") {
    two_view = initializeTwoView(tracks_, earliest_ns, t_b_ns, options_.focal_px, config);
    // "both": the multi-view start only once the counts are relaxed, i.e. the two-view start has
    // failed for init_relax_after_ms. Earlier it would pre-empt two-view starts that come within a
    // fraction of a second, and weak early starts cost accuracy for the rest of the run.
    if (method == "two-view" || !relaxed_counts) return two_view;
    // A two-view start that passes only thanks to the relaxed counts competes with the multi-view start
    // (init_weak_two_view compare or confirm): the one with more inliers wins.
    const std::string& weak_rule = options_.config.init_weak_two_view;
    const bool weak = weak_rule != "keep" && two_view.inliers < options_.config.init_min_inliers;
    if (two_view.ok && !weak) return two_view;
  }
  InitResult multi_view = initializeMultiView(tracks_, earliest_ns, t_b_ns, options_.focal_px, config);
  // Both methods' comparisons with a depth-reversed alternative are logged, whichever result is returned.
  multi_view.reversal_checks.insert(multi_view.reversal_checks.begin(), two_view.reversal_checks.begin(),
                                    two_view.reversal_checks.end());
  two_view.reversal_checks = multi_view.reversal_checks;
  if (two_view.ok) {
    if (!multi_view.ok && options_.config.init_weak_two_view == "confirm") {
      InitResult wait = two_view;
      wait.ok = false;
      wait.rejection = InitRejection::Agreement;
      wait.failure = fmt::format("weak two-view start ({} of {} features fit, need {} unrelaxed) not confirmed: {}",
                                 two_view.inliers, two_view.features, options_.config.init_min_inliers,
                                 multi_view.failure);
      return wait;
    }
    if (!multi_view.ok || multi_view.inliers <= two_view.inliers) return two_view;
    multi_view.replaced_two_view = true;
    return multi_view;
  }
  if (multi_view.ok || method == "multi-view") return multi_view;
  // Both failed: report the one that got further, and both reasons.
  InitResult& further = multi_view.rejection > two_view.rejection ? multi_view : two_view;
  further.failure = two_view.failure + multi_view.failure;
  return further;
}

bool SlidingWindowEstimator::relaxed(int64_t t_ns) const {
  return restart_relaxed_ ||
         durationSeconds(first_measurement_ns_, t_ns) * 1e3 >= options_.config.init_relax_after_ms;
}

int SlidingWindowEstimator::relaxations(int64_t t_ns) const {
  return relaxed(t_ns) ? (relaxed_again_ ? 2 : 1) : 0;
}

void SlidingWindowEstimator::rejectAttempt(int64_t t_ns, InitRejection rejection, std::string failure) {
  ++stats_.init_rejections[static_cast<int>(rejection)];
  if (stats_.init_attempt_log.size() < kMaxInitAttemptsLogged) {
    stats_.init_attempt_log.push_back(
        InitAttempt{t_ns, relaxations(t_ns), static_cast<int>(tracks_.size()), rejection, failure});
  } else {
    ++stats_.init_attempts_not_logged;
  }
  stats_.init_last_failure = std::move(failure);
}

BackendConfig SlidingWindowEstimator::initConfig(int64_t t_ns) const {
  BackendConfig config = options_.config;
  const double fraction = std::pow(config.init_relaxed_fraction, relaxations(t_ns));
  config.init_min_features = static_cast<int>(std::ceil(config.init_min_features * fraction));
  config.init_min_inliers = static_cast<int>(std::ceil(config.init_min_inliers * fraction));
  // The start after a segment that ended as a reversal (initConfig runs only while not tracking).
  const bool after_reversal = !stats_.segments.empty() && stats_.segments.back().end == SegmentEnd::kReversal;
  if (after_reversal && config.direction_audit_restart_rule != "same")
    config.init_depth_reversal = config.direction_audit_restart_rule;
  return config;
}

void SlidingWindowEstimator::updateRelaxedAgain(int64_t t_ns) {
  const double again_ms = options_.config.init_relax_again_after_ms;
  const double waited_ms = durationSeconds(first_measurement_ns_, t_ns) * 1e3;
  if (relaxed_again_ || !(again_ms > 0) || waited_ms < again_ms) return;
  relaxed_again_ = relaxed_feature_rejections_ > relaxed_other_rejections_;
  if (relaxed_again_) ++stats_.init_relaxed_again;
}

bool SlidingWindowEstimator::agreesWithPreviousAttempt(const InitResult& motion, int64_t t_ns) {
  const double bound = options_.config.init_agreement_deg;
  if (bound <= 0) return true;
  const std::optional<InitResult> previous = std::exchange(previous_start_motion_, motion);
  const double angle = previous ? travelAngleDeg(*previous, motion) : 180.0;
  if (angle <= bound) return true;
  rejectAttempt(t_ns, InitRejection::Agreement,
                previous ? fmt::format("{} direction of travel {:.1f} deg from the previous attempt's (need <= {})",
                                       motion.method, angle, bound)
                         : fmt::format("{} motion found, waiting for the next attempt to agree with it",
                                       motion.method));
  return false;
}

void SlidingWindowEstimator::tryInitialize(int64_t t_ns) {
  last_init_attempt_ns_ = t_ns;
  ++stats_.init_attempts;
  // Forget measurements too old to take part in any initialization window.
  const int64_t horizon = t_ns - std::llround(options_.config.init_window_ms * 1e6);
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    // One knot interval of margin: a feature must have a measurement at or before the horizon to be
    // interpolated there (FeatureTrack::pointAt).
    it->second.dropBefore(horizon - knot_dt_ns_);
    it = it->second.observations.empty() ? tracks_.erase(it) : std::next(it);
  }
  // The second view lags event time by one knot interval: the newest measurements of most features are
  // a little older than the newest event (tracker windows, min_dt), and both views need every feature.
  updateRelaxedAgain(t_ns);
  const BackendConfig config = initConfig(t_ns);
  const bool relaxed_counts = relaxed(t_ns);
  const InitResult motion =
      findInitialMotion(std::max(first_measurement_ns_, horizon), t_ns - knot_dt_ns_, config, relaxed_counts);
  for (const ReversalCheck& check : motion.reversal_checks) {
    if (stats_.init_reversal_log.size() < kMaxInitAttemptsLogged) stats_.init_reversal_log.push_back(check);
  }
  if (!motion.ok) {
    if (relaxed_counts) {
      const bool features = motion.rejection == InitRejection::Features;
      ++(features ? relaxed_feature_rejections_ : relaxed_other_rejections_);
    }
    previous_start_motion_.reset();
    rejectAttempt(t_ns, motion.rejection, motion.failure);
    return;
  }
  if (!agreesWithPreviousAttempt(motion, t_ns)) return;
  // Knots on a grid from t_a through the start's motion, at the monocular scale of 1 map unit per second
  // over its span (docs/backend.md).
  Trajectory trajectory = constantTwistTrajectory(motion, t_ns, knot_dt_ns_);
  if (trajectory.size() < 3) {
    rejectAttempt(t_ns, InitRejection::Features, "initialization window shorter than three knots");
    return;
  }
  trajectory_ = std::move(trajectory);
  const auto retriangulate = [this] {
    for (auto& [id, track] : tracks_) {
      track.triangulated = false;
      track.observations_at_last_attempt = 0;
    }
    triangulateTracks();
    return landmarkCount();
  };
  // The two views' points, taken before the tracks lose what lies before the window (interpolating at
  // t_a may need a measurement before it).
  const bool two_view = std::string_view(motion.method) == "two-view";
  const TwoViewPoints two_view_points =
      options_.config.init_two_view_landmarks && two_view ? twoViewPoints(motion.t_a_ns, motion.t_b_ns) : TwoViewPoints{};
  for (auto& [id, track] : tracks_) track.dropBefore(trajectory_.oldestTime());
  int landmarks = retriangulate();
  // A multi-view start's features need not span the window, so its fit can pass with few of them able
  // to make a landmark; it must triangulate as many landmarks as the two-view start needs inliers.
  const int min_landmarks = std::string_view(motion.method) == "multi-view" ? config.init_min_inliers
                                                                               : config.init_min_inliers / 2;
  // Too few: the trajectories between the two views miss the constant-twist knots; the two views
  // themselves are the five-point pose, so their correspondences make landmarks that the first solve
  // then fits the knots to (init_two_view_landmarks).
  if (landmarks < min_landmarks && !two_view_points.empty()) {
    const int added = triangulateFromTwoViews(two_view_points, motion.t_a_ns, motion.t_b_ns);
    if (added > 0) ++stats_.init_two_view_landmark_starts;
    landmarks += added;
  }
  // Still too few: the constant-twist knots may be off where the rotation rate changes within the window;
  // with init_refine_rotations their rotations are refitted to the tracks and the landmarks triangulated
  // again (docs/method/initialization.md, "First knots").
  if (landmarks < min_landmarks && options_.config.init_refine_rotations &&
      refineStartRotations(trajectory_, tracks_, options_.config.init_ransac_px / options_.focal_px).refined > 0) {
    ++stats_.init_rotation_refits;
    landmarks = retriangulate();
  }
  if (landmarks < min_landmarks) {
    rejectAttempt(t_ns, InitRejection::Landmarks,
                  fmt::format("{} pose found ({} inliers) but only {} landmarks triangulated (need {})",
                              motion.method, motion.inliers, landmarks, min_landmarks));
    trajectory_ = Trajectory();
    anchors_.clear();
    for (auto& [id, track] : tracks_) track.triangulated = false;
    return;
  }
  // Gauge (first pose) and scale (first velocity, loosely) anchored by a prior on the first knot.
  Knot& first = trajectory_.knots().begin()->second;
  gp::Mat12 covariance = gp::Mat12::Zero();
  covariance.diagonal().head<6>().setConstant(1e-8);
  covariance.diagonal().segment<3>(6).setConstant(std::pow(0.5 * first.twist().head<3>().norm() + 1e-3, 2));
  covariance.diagonal().tail<3>().setConstant(1.0);
  anchors_.clear();
  anchors_.push_back({FactorEntry{std::make_shared<StatePriorFactor>(first.T_w_c(), first.twist(), covariance),
                                  nullptr, {first.pose.data(), first.velocity.data()}},
                      {first.t_ns}});
  // Scale: the distance from the first knot to the last knot of the two-view span stays as initialized.
  Knot& far = std::prev(trajectory_.knots().upper_bound(motion.t_b_ns))->second;
  const double baseline = (far.T_w_c().translation() - first.T_w_c().translation()).norm();
  anchors_.push_back({FactorEntry{std::make_shared<ScaleAnchorFactor>(baseline, 1e-3 * baseline), nullptr,
                                  {first.pose.data(), far.pose.data()}},
                      {first.t_ns, far.t_ns}});
  if (motion.replaced_two_view) ++stats_.init_weak_two_view_replaced;
  if (motion.depth_reversed) ++stats_.init_depth_reversed;
  if (!stats_.initialized) {
    stats_.initialized = true;
    stats_.initialized_at_ns = t_ns;
    stats_.init_views = {motion.method, durationSeconds(motion.t_a_ns, motion.t_b_ns) * 1e3, motion.features,
                         motion.inliers, motion.parallax_px, landmarks};
  }
  previous_start_motion_.reset();
  tracking_ = true;
  Segment segment;
  segment.initialized_at_ns = t_ns;
  stats_.segments.push_back(segment);
  last_supported_ns_ = trajectory_.newestTime();
  segment_depth_ = 0;
  stats_.knots += trajectory_.size();
  const auto start = Clock::now();
  auto [iterations, cost] = solve(std::max(options_.config.max_iterations, 20));
  removeOutliers();
  // The trajectories that failed against the constant-twist knots, tried again against the solved ones
  // (init_retriangulate; docs/method/initialization.md, "First knots").
  if (options_.config.init_retriangulate && retriangulateUntriangulated() > 0) {
    ++stats_.init_retriangulations;
    std::tie(iterations, cost) = solve(options_.config.max_iterations);
    removeOutliers();
  }
  UpdateRecord record;
  record.event_t_ns = t_ns;
  record.window_knots = static_cast<int>(trajectory_.size());
  countWindow(record);
  record.iterations = iterations;
  record.final_cost = cost;
  record.solve_ms = msSince(start);
  record.total_ms = record.solve_ms;
  records_.push_back(record);
}

SlidingWindowEstimator::TwoViewPoints SlidingWindowEstimator::twoViewPoints(int64_t t_a_ns, int64_t t_b_ns) const {
  TwoViewPoints points;
  for (const auto& [id, track] : tracks_) {
    const auto a = track.pointAt(t_a_ns), b = track.pointAt(t_b_ns);
    if (a && b) points[id] = {*a, *b};
  }
  return points;
}

int SlidingWindowEstimator::triangulateFromTwoViews(const TwoViewPoints& points, int64_t t_a_ns, int64_t t_b_ns) {
  const TriangulationOptions tri = triangulationOptions();
  const lie::SE3 T_w_a = trajectory_.pose(t_a_ns), T_w_b = trajectory_.pose(t_b_ns);
  int added = 0;
  for (const auto& [id, ab] : points) {
    const auto it = tracks_.find(id);
    if (it == tracks_.end() || it->second.triangulated) continue;
    FeatureTrack& track = it->second;
    const TriangulationResult result = triangulate({{T_w_a, ab.first}, {T_w_b, ab.second}}, tri);
    if (!result.p_w) continue;
    makeLandmark(track, *result.p_w);
    ++added;
  }
  return added;
}

int SlidingWindowEstimator::retriangulateUntriangulated() {
  const int before = landmarkCount();
  for (auto& [id, track] : tracks_)
    if (!track.triangulated) track.observations_at_last_attempt = 0;
  triangulateTracks();
  return landmarkCount() - before;
}

void SlidingWindowEstimator::update(int64_t t_ns) {
  const auto start = Clock::now();
  UpdateRecord record;
  record.event_t_ns = t_ns;
  triangulateTracks();
  record.triangulate_ms = msSince(start);
  const auto t_marg = Clock::now();
  if (options_.marginalize) marginalizeDynamic();
  record.marginalize_ms = msSince(t_marg);
  const auto t_solve = Clock::now();
  const auto [iterations, cost] = solve(options_.config.max_iterations);
  const auto t_outliers = Clock::now();
  removeOutliers();
  record.outliers_ms = msSince(t_outliers);
  record.solve_ms = msSince(t_solve);
  record.solve_build_ms = last_solve_times_.build_ms;
  record.solve_residuals_ms = last_solve_times_.residuals_ms;
  record.solve_jacobians_ms = last_solve_times_.jacobians_ms;
  record.solve_linear_ms = last_solve_times_.linear_ms;
  record.solve_other_ms = last_solve_times_.other_ms;
  record.iterations = iterations;
  record.final_cost = cost;
  record.window_knots = static_cast<int>(trajectory_.size());
  countWindow(record);
  record.total_ms = msSince(start);
  records_.push_back(record);
  ++stats_.updates;
  stats_.max_window_knots = std::max(stats_.max_window_knots, record.window_knots);
  checkTracking(t_ns, record.landmarks);
  auditDirection(t_ns);
  if (tracking_ && options_.config.loss_write_accepted_window) {
    accepted_window_.clear();
    for (const auto& [t, knot] : trajectory_.knots()) accepted_window_.push_back(knot);
  }
}

void SlidingWindowEstimator::countWindow(UpdateRecord& record) const {
  const int64_t recent_from = trajectory_.newestTime() - knot_dt_ns_;
  for (const auto& [id, track] : tracks_) {
    if (!track.triangulated) continue;
    ++record.landmarks;
    for (const auto& o : track.observations) record.measurements += trajectory_.covers(o.t_ns);
    record.recent_landmarks += !track.observations.empty() && track.observations.back().t_ns > recent_from &&
                               trajectory_.covers(track.observations.back().t_ns);
  }
}

void SlidingWindowEstimator::checkTracking(int64_t t_ns, int landmarks) {
  const BackendConfig& c = options_.config;
  const int64_t newest = trajectory_.newestTime();
  for (const auto& [t, knot] : trajectory_.knots()) {
    if (!finiteKnot(knot)) {
      loseTrackingAtFailedSolve(SegmentEnd::kNonFinite, t_ns);
      return;
    }
  }
  // A solve that no longer explains its measurements: the window's estimate is not kept.
  if (c.loss_max_median_px > 0 && landmarks > 0 && last_median_residual_px_ > c.loss_max_median_px) {
    loseTrackingAtFailedSolve(SegmentEnd::kResidual, t_ns);
    return;
  }
  stats_.max_median_residual_px = std::max(stats_.max_median_residual_px, last_median_residual_px_);
  // Scale collapse (or blow-up): the map's depths drift away from those the segment started with.
  const double depth = medianLandmarkDepth(trajectory_.knots().rbegin()->second.T_w_c().inverse(), 10);
  if (depth > 0 && segment_depth_ == 0) segment_depth_ = depth;
  const double ratio = depth > 0 ? std::max(depth / segment_depth_, segment_depth_ / depth) : 0.0;
  if (c.loss_depth_ratio > 0 && ratio > c.loss_depth_ratio) {
    loseTrackingAtFailedSolve(SegmentEnd::kDepth, t_ns);
    return;
  }
  stats_.max_depth_ratio = std::max(stats_.max_depth_ratio, ratio);
  if (landmarks >= c.loss_min_landmarks) {
    last_supported_ns_ = newest;
  } else if (c.loss_unsupported_ms > 0 && durationSeconds(last_supported_ns_, newest) * 1e3 > c.loss_unsupported_ms) {
    loseTracking(SegmentEnd::kUnsupported, t_ns, last_supported_ns_, t_ns);
  }
}

void SlidingWindowEstimator::auditDirection(int64_t t_ns) {
  const BackendConfig& c = options_.config;
  if (c.direction_audit == "off" || !tracking_ || trajectory_.empty()) return;
  if (durationSeconds(stats_.segments.back().initialized_at_ns, t_ns) * 1e3 > c.direction_audit_ms) return;
  // The second time lags the newest knot by one interval, as a start's does: most features' newest
  // measurements are a little older than the newest event.
  const int64_t t_b = trajectory_.newestTime() - knot_dt_ns_;
  const int64_t t_a = t_b - secondsToNs(c.direction_audit_span_ms * 1e-3);
  // As many trajectories as a once-relaxed start needs: fewer hold too little evidence to end a segment.
  const int min_features = static_cast<int>(std::ceil(c.init_min_features * c.init_relaxed_fraction));
  std::optional<ReversalCheck> check = backend::auditDirection(trajectory_, tracks_, t_a, t_b, options_.focal_px,
                                                              c.init_ransac_px, c.direction_audit_parallax_px,
                                                              min_features);
  if (!check) return;
  ++stats_.direction_audits;
  const bool against = check->found && check->reversed_cost < (1.0 - c.direction_audit_margin) * check->cost;
  audit_votes_ = against ? audit_votes_ + 1 : 0;
  stats_.direction_audit_votes += against;
  if (against) check->decision = audit_votes_ >= c.direction_audit_votes && c.direction_audit == "restart"
                                     ? "restart" : "against";
  if (stats_.init_reversal_log.size() < kMaxInitAttemptsLogged) stats_.init_reversal_log.push_back(*check);
  if (std::string_view(check->decision) == "restart") {
    // The segment's knots are written as estimated (its end says why); the start begins again.
    loseTracking(SegmentEnd::kReversal, t_ns, trajectory_.newestTime(), t_ns);
  }
}

void SlidingWindowEstimator::loseTrackingAtFailedSolve(SegmentEnd reason, int64_t t_ns) {
  constexpr int64_t kNone = std::numeric_limits<int64_t>::min();
  // accepted_window_ is kept only with loss_write_accepted_window. Knots marginalized since the accepted
  // update were written with its values; the rest of its window is written now, and the failed solve's
  // knots it covers leave the window unwritten; loseTracking drops (and counts) the newer ones.
  const Segment& segment = stats_.segments.back();
  const int64_t written_until = segment.knots > 0 ? segment.t1_ns : kNone;
  int64_t kept_until = written_until;
  for (const Knot& knot : accepted_window_) {
    if (knot.t_ns <= written_until || !finiteKnot(knot)) continue;
    finalizeKnot(knot);
    kept_until = knot.t_ns;
  }
  auto& knots = trajectory_.knots();
  knots.erase(knots.begin(), knots.upper_bound(kept_until));
  loseTracking(reason, t_ns, kNone, t_ns);
}

void SlidingWindowEstimator::loseTracking(SegmentEnd reason, int64_t t_ns, int64_t keep_until_ns,
                                          int64_t reset_ns) {
  for (const auto& [t, knot] : trajectory_.knots()) {
    if (t <= keep_until_ns && finiteKnot(knot)) {
      finalizeKnot(knot);
    } else {
      ++stats_.knots_dropped_at_loss;
    }
  }
  if (!trajectory_.empty() && keep_until_ns >= trajectory_.newestTime()) {  // kept whole: so are its landmarks
    for (const auto& [id, track] : tracks_)
      if (track.triangulated) finalizeLandmark(track);
  }
  final_velocity_.flush(final_knots_);  // the segment's last knots
  Segment& segment = stats_.segments.back();
  segment.end = reason;
  segment.ended_at_ns = t_ns;
  trajectory_ = Trajectory();
  accepted_window_.clear();
  prior_.reset();
  anchors_.clear();
  tracking_ = false;
  segment_depth_ = 0;
  audit_votes_ = 0;
  restartInitialization(reset_ns);
}

void SlidingWindowEstimator::restartInitialization(int64_t reset_ns) {
  tracks_.clear();
  first_measurement_ns_ = -1;
  last_init_attempt_ns_.reset();
  previous_start_motion_.reset();
  relaxed_feature_rejections_ = relaxed_other_rejections_ = 0;
  // relaxed_again_ still says whether the previous start was granted the second relaxation.
  restart_relaxed_ = options_.config.init_restart_short_relaxed && relaxed_again_;
  relaxed_again_ = restart_relaxed_;
  if (restart_relaxed_) ++stats_.init_restarts_relaxed;
  reset_ns_ = reset_ns;
}

bool SlidingWindowEstimator::DepthGate::admits(const double* p_w) const {
  const double z = (T_c_w * Eigen::Map<const Eigen::Vector3d>(p_w)).z();
  return z > min_depth && z < max_depth;
}

SlidingWindowEstimator::DepthGate SlidingWindowEstimator::depthGate() const {
  DepthGate gate;
  const double range = options_.config.landmark_depth_range;
  if (range <= 0 || trajectory_.size() == 0) return gate;
  gate.T_c_w = trajectory_.knots().rbegin()->second.T_w_c().inverse();
  const double median = medianLandmarkDepth(gate.T_c_w, 10);
  if (median <= 0) return gate;
  gate.min_depth = median / range;
  gate.max_depth = median * range;
  return gate;
}

double SlidingWindowEstimator::medianLandmarkDepth(const lie::SE3& T_c_w, std::size_t min_count) const {
  std::vector<double> depths;
  for (const auto& [id, track] : tracks_)
    if (track.triangulated) depths.push_back((T_c_w * Eigen::Map<const Eigen::Vector3d>(track.p_w.data())).z());
  if (depths.empty() || depths.size() < min_count) return 0;
  return std::max(0.0, upperMedian(depths));
}

void SlidingWindowEstimator::triangulateTracks() {
  const DepthGate depth_gate = depthGate();
  const BackendConfig& c = options_.config;
  const TriangulationOptions tri = triangulationOptions();
  // triangulation_views: in an open segment, the views after the latest solve's newest knot lie on knots
  // predicted at constant velocity (TriangulationViews).
  const TriangulationViews rule = tracking_ && solved_until_ns_ >= 0 ? triangulation_views_ : TriangulationViews::kAll;
  const std::size_t min_views = static_cast<std::size_t>(c.min_track_measurements);
  RejoinOptions rejoin;
  rejoin.max_error = tracking_ ? normalizedThreshold(c.landmark_rejoin_px) : 0.0;
  rejoin.min_depth = c.min_depth;
  rejoin.max_gap_ns = std::llround(c.landmark_rejoin_max_gap_ms * 1e6);
  struct Rejoin {
    int64_t from, to;        // the new trajectory, the landmark it extends
    Eigen::Vector2d offset;  // its measurements' mean offset from the landmark's projection
  };
  std::vector<Rejoin> rejoins;
  std::set<int64_t> rejoined;                        // landmarks claimed in this pass
  for (auto& [id, track] : tracks_) {
    if (track.triangulated) continue;
    std::vector<TriangulationView> views;
    for (const FixedView& v : track.fixed_views) views.push_back({v.T_w_c, v.xn});
    std::size_t solved = views.size();  // the first `solved` views lie at or before solved_until_ns_
    for (const Observation& o : track.observations) {
      if (!trajectory_.covers(o.t_ns)) continue;
      views.push_back({trajectory_.pose(o.t_ns), o.xn});
      if (o.t_ns <= solved_until_ns_) solved = views.size();
    }
    // A trajectory is tried when it has enough views for its rule and a view was added since its last try.
    const std::size_t usable = rule == TriangulationViews::kSolved ? solved : views.size();
    if (usable < min_views) continue;
    if (usable == track.observations_at_last_attempt) continue;
    track.observations_at_last_attempt = usable;
    if (rejoin.max_error > 0) {
      const RejoinMatch match = findRejoinLandmark(views, track.firstTime(), tracks_, rejoin);
      if (match.candidates_fitting > 1) ++stats_.rejoins_ambiguous;
      if (match.key && rejoined.insert(*match.key).second) {
        rejoins.push_back({id, *match.key, match.offset});
        continue;
      }
    }
    const TriangulationResult result = triangulateTrajectory(views, solved, rule, min_views, tri);
    if (!result.p_w) {
      ++stats_.triangulation_failures[static_cast<std::size_t>(result.failure)];
      continue;
    }
    if (!depth_gate.admits(result.p_w->data())) {
      ++stats_.landmarks_depth_rejected;
      continue;
    }
    makeLandmark(track, *result.p_w);
  }
  for (const Rejoin& r : rejoins) rejoinLandmark(r.from, r.to, r.offset);
}

void SlidingWindowEstimator::rejoinLandmark(int64_t from, int64_t to, const Eigen::Vector2d& offset) {
  FeatureTrack& source = tracks_.at(from);
  FeatureTrack& landmark = tracks_.at(to);
  // The new tracker may sit on the corner a pixel or two from where the old one sat: its mean offset
  // from the landmark's projection is removed from its measurements, now and later.
  for (Observation& o : source.observations) o.xn -= offset;
  for (int64_t feature : featuresFeeding(from)) {
    const auto [entry, inserted] = rejoin_offsets_.emplace(feature, offset);
    if (!inserted) entry->second += offset;
  }
  // findRejoinLandmark took only landmarks measured last before the new trajectory's first measurement.
  landmark.observations.insert(landmark.observations.end(), source.observations.begin(), source.observations.end());
  // A feature that still fed the landmark (quiet, not ended) would now interleave with the new one: its
  // later measurements are ignored. One that has ended sends none.
  if (!landmark.feature_ended) {
    for (int64_t feature : featuresFeeding(to)) {
      split_aliases_.erase(feature);
      superseded_features_.insert(feature);
    }
  }
  // The new trajectory's feature now extends the landmark.
  for (int64_t feature : featuresFeeding(from)) split_aliases_[feature] = to;
  landmark.feature_ended = source.feature_ended;
  tracks_.erase(from);
  ++stats_.landmarks_rejoined;
}

std::vector<int64_t> SlidingWindowEstimator::featuresFeeding(int64_t key) const {
  std::vector<int64_t> features;
  for (const auto& [feature, alias] : split_aliases_) {
    if (alias == key) features.push_back(feature);
  }
  if (key < kFirstSplitId && !split_aliases_.count(key)) features.push_back(key);
  return features;
}

TriangulationOptions SlidingWindowEstimator::triangulationOptions() const {
  const BackendConfig& c = options_.config;
  TriangulationOptions tri;
  tri.min_parallax_deg = c.min_parallax_deg;
  tri.max_error = normalizedThreshold(c.max_triangulation_px);
  // A start counts its landmarks by the largest error: its first knots are a constant-twist fit, and
  // the RMS test there lets a start come earlier on a poorer map (docs/results/window_landmarks.md).
  tri.rms_error = c.triangulation_error == "rms" && tracking_;
  tri.min_depth = c.min_depth;
  return tri;
}

void SlidingWindowEstimator::makeLandmark(FeatureTrack& track, const Eigen::Vector3d& p_w) {
  track.triangulated = true;
  Eigen::Map<Eigen::Vector3d>(track.p_w.data()) = p_w;
  ++stats_.landmarks_created;
}

int SlidingWindowEstimator::landmarkCount() const {
  int count = 0;
  for (const auto& [id, track] : tracks_) count += track.triangulated;
  return count;
}

void SlidingWindowEstimator::buildFactors(std::vector<FactorEntry>& factors, std::map<double*, BlockKind>& kinds,
                                          std::vector<ProjectionSource>* projection_sources) {
  factors.clear();
  kinds.clear();
  if (projection_sources) projection_sources->clear();
  auto& knots = trajectory_.knots();
  for (auto& [t, knot] : knots) {
    kinds[knot.pose.data()] = BlockKind::kPose;
    kinds[knot.velocity.data()] = BlockKind::kEuclidean;
  }
  for (auto it = knots.begin(); std::next(it) != knots.end(); ++it) {
    Knot& a = it->second;
    Knot& b = std::next(it)->second;
    factors.push_back({std::make_shared<WnoaPriorFactor>(a.t_ns, b.t_ns, Q_c_, gp::kDefaultSeriesOrder,
                                                         options_.config.scale_free_prior),
                       nullptr,
                       {a.pose.data(), a.velocity.data(), b.pose.data(), b.velocity.data()}});
  }
  const double sigma = normalizedThreshold(options_.config.pixel_sigma);
  std::map<int64_t, std::shared_ptr<SegmentCache>> segment_caches;  // by the segment's first knot time
  for (auto& [id, track] : tracks_) {
    if (!track.triangulated) continue;
    kinds[track.p_w.data()] = BlockKind::kEuclidean;
    for (std::size_t i = 0; i < track.observations.size(); ++i) {
      const Observation& o = track.observations[i];
      const auto seg = trajectory_.segment(o.t_ns);
      if (!seg) continue;  // later than the newest knot: waits for the next knot
      Knot& a = *const_cast<Knot*>(seg->first);
      Knot& b = *const_cast<Knot*>(seg->second);
      auto factor = std::make_shared<GpProjectionFactor>(o.xn, o.t_ns, a.t_ns, b.t_ns, sigma);
      std::shared_ptr<SegmentCache>& cache = segment_caches[a.t_ns];
      if (!cache) cache = std::make_shared<SegmentCache>();
      factor->setSegmentCache(cache);
      factors.push_back({std::move(factor), huber_,
                         {a.pose.data(), a.velocity.data(), b.pose.data(), b.velocity.data(), track.p_w.data()}});
      if (projection_sources) projection_sources->push_back({&track, i, factors.size() - 1});
    }
    for (const FixedView& v : track.fixed_views) {
      factors.push_back({std::make_shared<FixedPoseProjectionFactor>(v.T_w_c, v.xn, sigma), huber_, {track.p_w.data()}});
    }
  }
  if (prior_) factors.push_back(*prior_);
  for (const Anchor& anchor : anchors_) factors.push_back(anchor.factor);
}

std::pair<int, double> SlidingWindowEstimator::solve(int max_iterations) {
  const auto build_start = Clock::now();
  solved_until_ns_ = trajectory_.newestTime();
  std::vector<FactorEntry> factors;
  std::map<double*, BlockKind> kinds;
  buildFactors(factors, kinds, nullptr);
  std::vector<double> residual_scratch;
  std::vector<FactorEntry> valid_factors;
  for (FactorEntry& f : factors) {
    // A projection whose point is behind the camera at the start would stop the solve: leave it out.
    residual_scratch.resize(static_cast<std::size_t>(f.cost->num_residuals()));
    if (!f.cost->Evaluate(f.blocks.data(), residual_scratch.data(), nullptr)) continue;
    valid_factors.push_back(std::move(f));
  }
  if (options_.config.window_solver == "builtin" && !options_.sparse_linear_solver)
    return solveBuiltin(valid_factors, kinds, max_iterations, msSince(build_start));
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const FactorEntry& f : valid_factors) problem.AddResidualBlock(f.cost.get(), f.loss.get(), f.blocks);
  for (const auto& [block, kind] : kinds) {
    if (kind == BlockKind::kPose && problem.HasParameterBlock(block)) problem.SetManifold(block, se3_manifold_.get());
  }
  for (const auto& [t, knot] : trajectory_.knots()) {
    if (!isFrozen(knot)) continue;
    for (const double* b : {knot.pose.data(), knot.velocity.data()})
      if (problem.HasParameterBlock(b)) problem.SetParameterBlockConstant(b);
  }
  // No explicit elimination ordering: Ceres's own Schur ordering is computed from the program order
  // (insertion order, deterministic) and finds the landmarks as the independent set. An explicit
  // ParameterBlockOrdering keeps its groups as sets of pointers, i.e. in heap-address order, which
  // would make the floating-point result depend on where the allocator put the blocks.
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = options_.sparse_linear_solver ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.max_num_iterations = max_iterations;
  solver_options.function_tolerance = options_.config.function_tolerance;
  solver_options.initial_trust_region_radius = options_.config.initial_trust_region_radius;
  solver_options.num_threads = options_.config.solver_threads;
  solver_options.logging_type = ceres::SILENT;
  if (options_.real_time) solver_options.max_solver_time_in_seconds = options_.config.max_solver_time_s;
  ceres::Solver::Summary summary;
  const double build_ms = msSince(build_start);
  ceres::Solve(solver_options, &problem, &summary);
  SolveTimes& times = last_solve_times_;
  times.build_ms = build_ms;
  times.residuals_ms = summary.residual_evaluation_time_in_seconds * 1e3;
  times.jacobians_ms = summary.jacobian_evaluation_time_in_seconds * 1e3;
  times.linear_ms = summary.linear_solver_time_in_seconds * 1e3;
  times.other_ms =
      std::max(0.0, summary.total_time_in_seconds * 1e3 - times.residuals_ms - times.jacobians_ms - times.linear_ms);
  return {static_cast<int>(summary.iterations.size()), summary.final_cost};
}

std::pair<int, double> SlidingWindowEstimator::solveBuiltin(const std::vector<FactorEntry>& factors,
                                                            const std::map<double*, BlockKind>& kinds,
                                                            int max_iterations, double build_ms) {
  std::set<const double*> knot_blocks, constant;
  for (const auto& [t, knot] : trajectory_.knots()) {
    knot_blocks.insert({knot.pose.data(), knot.velocity.data()});
    if (isFrozen(knot)) constant.insert({knot.pose.data(), knot.velocity.data()});
  }
  std::set<const double*> landmarks;
  for (const auto& [block, kind] : kinds)
    if (!knot_blocks.count(block)) landmarks.insert(block);
  WindowSolverOptions solver_options;
  solver_options.max_iterations = max_iterations;
  solver_options.function_tolerance = options_.config.function_tolerance;
  solver_options.initial_radius = options_.config.initial_trust_region_radius;
  solver_options.relinearize_every = options_.config.relinearize_every;
  solver_options.threads = options_.config.solver_threads;
  if (options_.real_time) solver_options.max_time_s = options_.config.max_solver_time_s;
  const WindowSolverSummary summary =
      solveWindow(factors, kinds, landmarks, constant, *se3_manifold_, solver_options, solver_workspace_.get());
  SolveTimes& times = last_solve_times_;
  times.build_ms = build_ms;
  times.residuals_ms = summary.residuals_ms;
  times.jacobians_ms = summary.jacobians_ms;
  times.linear_ms = summary.linear_ms;
  times.other_ms = std::max(0.0, summary.total_ms - times.residuals_ms - times.jacobians_ms - times.linear_ms);
  return {summary.iterations, summary.final_cost};
}

void SlidingWindowEstimator::marginalizeDynamic() {
  const BackendConfig& c = options_.config;
  std::vector<int64_t> times;
  for (const auto& [t, knot] : trajectory_.knots()) times.push_back(t);
  const int n = static_cast<int>(times.size());
  if (n <= c.window_min_knots) return;

  // Paper Alg. 1: a trajectory is marked if it started in [t_0, t_1) and ended before t_ε.
  const int64_t t0 = times[0], t1 = times[1], tN = times.back();
  const auto t_eps = static_cast<int64_t>(std::llround((1.0 - c.marginalization_epsilon) * static_cast<double>(t0) +
                                                       c.marginalization_epsilon * static_cast<double>(tN)));
  std::set<int64_t> marked;
  for (const auto& [id, track] : tracks_) {
    if (!track.observations.empty() && track.firstTime() >= t0 && track.firstTime() < t1 && track.lastTime() < t_eps)
      marked.insert(id);
  }
  // Walk from the oldest knot while the window is larger than N_min and every trajectory observed in
  // [t_k, t_{k+1}] is marked; beyond N_max, marginalize anyway (observations tying it to active
  // trajectories are dropped).
  int count = 0;
  bool forced = false;
  while (n - count > c.window_min_knots && count < n - 1) {
    bool all_marked = true;
    for (const auto& [id, track] : tracks_) {
      if (!marked.count(id) && track.observedIn(times[count], times[count + 1])) {
        all_marked = false;
        break;
      }
    }
    if (!all_marked) {
      if (n - count <= c.window_max_knots) break;
      forced = true;
    }
    ++count;
  }
  if (count == 0) return;
  const int64_t new_oldest = times[count];

  // Observations that would tie a marginalized knot to an unmarked trajectory (forced case):
  //  - of a trajectory never triangulated: they simply leave with the knots;
  //  - of a landmark, by forced_marginalization:
  //      fixed_poses  they stay as projections from their interpolated poses, now held fixed;
  //      prior        they enter the Schur complement and the landmark joins the prior's blanket;
  //      drop         they are dropped, and the prior stays on knots only;
  //    with fixed_poses or prior, a landmark with no measurement left in the window leaves with the knots.
  // A measurement exactly at the new oldest knot time uses the segment after it: kept.
  const std::string& mode = c.forced_marginalization;
  std::set<int64_t> leaving = marked;
  for (auto& [id, track] : tracks_) {
    if (marked.count(id) || track.observations.empty() || track.firstTime() >= new_oldest) continue;
    if (!track.triangulated) {
      stats_.observations_dropped_untriangulated += track.dropBefore(new_oldest);
      continue;
    }
    if (mode == "drop") {
      stats_.observations_dropped_forced += track.dropBefore(new_oldest);
      continue;
    }
    if (mode == "fixed_poses") {
      for (const Observation& o : track.observations) {
        if (o.t_ns >= new_oldest) break;
        track.fixed_views.push_back({trajectory_.pose(o.t_ns), o.xn});
      }
      stats_.observations_fixed_pose += track.dropBefore(new_oldest);
    }
    if (track.observations.empty() || track.lastTime() < new_oldest) leaving.insert(id);
  }
  if (forced) ++stats_.forced_marginalizations;

  std::set<double*> to_marginalize;
  for (int k = 0; k < count; ++k) {
    Knot* knot = trajectory_.find(times[k]);
    to_marginalize.insert(knot->pose.data());
    to_marginalize.insert(knot->velocity.data());
  }
  for (int64_t id : leaving) {
    if (tracks_[id].triangulated) to_marginalize.insert(tracks_[id].p_w.data());
  }
  std::vector<FactorEntry> factors;
  std::map<double*, BlockKind> kinds;
  buildFactors(factors, kinds, nullptr);
  std::vector<const FactorEntry*> touching;
  for (const FactorEntry& f : factors) {
    const bool touches = std::any_of(f.blocks.begin(), f.blocks.end(), [&](double* b) { return to_marginalize.count(b) > 0; });
    if (touches || (prior_ && f.cost == prior_->cost)) touching.push_back(&f);
  }
  const MarginalizationResult result = marginalize(touching, to_marginalize, kinds);
  ++stats_.marginalizations;
  stats_.last_prior_rank = result.prior_rank;

  // Copy the prior's blocks before the knots they may point to are erased (they are all kept knots).
  if (result.prior) {
    prior_ = FactorEntry{result.prior, nullptr, result.prior_blocks};
  } else {
    prior_.reset();
  }
  for (int k = 0; k < count; ++k) {
    finalizeKnot(*trajectory_.find(times[k]));
    anchors_.erase(std::remove_if(anchors_.begin(), anchors_.end(),
                                  [&](const Anchor& a) {
                                    return std::find(a.knots.begin(), a.knots.end(), times[k]) != a.knots.end();
                                  }),
                   anchors_.end());
    trajectory_.remove(times[k]);
    ++stats_.knots_marginalized;
  }
  for (auto& [id, track] : tracks_) {
    if (!leaving.count(id)) stats_.observations_marginalized += track.dropBefore(new_oldest);
  }
  renewScaleAnchor();
  for (int64_t id : leaving) {
    auto it = tracks_.find(id);
    if (it->second.triangulated) {
      finalizeLandmark(it->second);
      ++stats_.landmarks_marginalized;
    } else {
      stats_.observations_dropped_untriangulated += it->second.observations.size();
    }
    tracks_.erase(it);
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    it = it->second.observations.empty() ? tracks_.erase(it) : std::next(it);
  }
}

void SlidingWindowEstimator::releaseFromPrior(double* landmark) {
  if (!prior_ || std::find(prior_->blocks.begin(), prior_->blocks.end(), landmark) == prior_->blocks.end()) return;
  // The landmark stops being a variable: marginalize it out of the prior alone (a Schur complement of
  // the prior's own information), so what it said about the other blocks stays and it is not pinned.
  const auto* linear = dynamic_cast<const LinearPriorFactor*>(prior_->cost.get());
  std::map<double*, BlockKind> kinds;
  for (std::size_t i = 0; i < prior_->blocks.size(); ++i)
    kinds[prior_->blocks[i]] =
        linear->blocks()[i].kind == LinearPriorBlock::Kind::kPose ? BlockKind::kPose : BlockKind::kEuclidean;
  const MarginalizationResult result = marginalize({&*prior_}, {landmark}, kinds);
  if (result.prior) {
    prior_ = FactorEntry{result.prior, nullptr, result.prior_blocks};
  } else {
    prior_.reset();
  }
  ++stats_.landmarks_released;
}

void SlidingWindowEstimator::untriangulate(FeatureTrack& track) {
  releaseFromPrior(track.p_w.data());
  track.triangulated = false;
  track.observations_at_last_attempt = 0;
}

void SlidingWindowEstimator::renewScaleAnchor() {
  // The WNOA prior is not scale invariant and keeps pulling a monocular map toward zero scale; the
  // marginalization prior carries the initial anchor only weakly once observations are dropped (N_max).
  // So whenever no scale anchor is left in the window, hold the current distance between the oldest knot
  // and the knot farthest from it (a pseudo-measurement on the one unobservable scale direction).
  const bool has_anchor = std::any_of(anchors_.begin(), anchors_.end(), [](const Anchor& a) { return a.knots.size() == 2; });
  if (has_anchor || trajectory_.size() < 3 || options_.config.scale_anchor_sigma <= 0) return;
  Knot& oldest = trajectory_.knots().begin()->second;
  Knot* farthest = nullptr;
  double distance = 0;
  for (auto& [t, knot] : trajectory_.knots()) {
    const double d = (knot.T_w_c().translation() - oldest.T_w_c().translation()).norm();
    if (d > distance) {
      distance = d;
      farthest = &knot;
    }
  }
  // Map speed is normalized to ~1 unit/s at initialization: require a baseline worth anchoring.
  const double span_s = durationSeconds(trajectory_.oldestTime(), trajectory_.newestTime());
  if (farthest == nullptr || distance < 0.1 * span_s) return;
  anchors_.push_back({FactorEntry{std::make_shared<ScaleAnchorFactor>(distance, options_.config.scale_anchor_sigma * distance),
                                  nullptr, {oldest.pose.data(), farthest->pose.data()}},
                      {oldest.t_ns, farthest->t_ns}});
  ++stats_.scale_anchors;
}

void SlidingWindowEstimator::removeOutliers() {
  std::vector<FactorEntry> factors;
  std::map<double*, BlockKind> kinds;
  std::vector<ProjectionSource> sources;
  buildFactors(factors, kinds, &sources);
  // Residuals are whitened by pixel_sigma: thresholds in pixels divide by it.
  const double limit = options_.config.outlier_px / options_.config.pixel_sigma;
  const double track_limit = options_.config.track_outlier_rms_px / options_.config.pixel_sigma;
  struct TrackResiduals {
    std::vector<std::pair<std::size_t, double>> norms;  ///< (observation index, whitened norm)
  };
  std::map<FeatureTrack*, TrackResiduals> per_track;
  // The measurements of the newest knot interval: what this update added. Older ones were pruned by
  // earlier calls, so their residuals would hide a window that stopped fitting.
  std::vector<double> norms_px;
  const int64_t recent_from =
      trajectory_.size() >= 2 ? std::prev(trajectory_.knots().end(), 2)->first : std::numeric_limits<int64_t>::min();
  double residual[2];
  for (const ProjectionSource& source : sources) {
    const FactorEntry& f = factors[source.factor];
    TrackResiduals& r = per_track[source.track];
    const bool ok = f.cost->Evaluate(f.blocks.data(), residual, nullptr);
    const double norm = ok ? std::hypot(residual[0], residual[1]) : std::numeric_limits<double>::infinity();
    r.norms.emplace_back(source.observation, norm);
    if (source.track->observations[source.observation].t_ns > recent_from)
      norms_px.push_back(norm * options_.config.pixel_sigma);
  }
  last_median_residual_px_ = 0;
  if (norms_px.size() >= 10) {
    last_median_residual_px_ = upperMedian(norms_px);
  }
  const DepthGate depth_gate = depthGate();
  for (auto& [track, r] : per_track) {
    if (!depth_gate.admits(track->p_w.data())) {
      // A low-parallax landmark that ran away (or collapsed toward the camera): retriangulated later,
      // with the parallax it has gained by then.
      untriangulate(*track);
      ++stats_.landmarks_depth_reset;
      continue;
    }
    std::sort(r.norms.begin(), r.norms.end());
    splitDriftedTail(*track, r.norms);  // drops the tail's norms from r.norms when it splits
    double sum_squared = 0;
    std::vector<std::size_t> bad;  // observation indices beyond `limit`
    for (const auto& [observation, norm] : r.norms) {
      sum_squared += std::isfinite(norm) ? norm * norm : limit * limit;
      if (norm > limit) bad.push_back(observation);
    }
    // A landmark that does not fit as a whole is no fixed scene point (or its tracker drifted): its
    // measurements bias every pose they touch, so the trajectory leaves the estimation for good.
    if (track_limit > 0 && !r.norms.empty() &&
        std::sqrt(sum_squared / static_cast<double>(r.norms.size())) > track_limit) {
      releaseFromPrior(track->p_w.data());
      rejected_features_.insert(track->id);
      track->observations.clear();  // erased from tracks_ below
      track->triangulated = false;
      ++stats_.tracks_rejected;
      continue;
    }
    for (auto it = bad.rbegin(); it != bad.rend(); ++it) {
      track->observations.erase(track->observations.begin() + static_cast<std::ptrdiff_t>(*it));
      ++stats_.outliers_removed;
    }
    if (bad.empty()) continue;
    int inside = 0;
    for (const auto& o : track->observations) inside += trajectory_.covers(o.t_ns);
    if (inside < 2) {  // not enough left to constrain the landmark: back to an untriangulated trajectory
      untriangulate(*track);
      ++stats_.landmarks_lost;
    }
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    it = it->second.observations.empty() ? tracks_.erase(it) : std::next(it);
  }
}

void SlidingWindowEstimator::splitDriftedTail(FeatureTrack& track,
                                              std::vector<std::pair<std::size_t, double>>& norms) {
  const double split_limit = options_.config.track_split_px / options_.config.pixel_sigma;
  const auto min_run = static_cast<std::size_t>(options_.config.track_split_min_measurements);
  if (split_limit <= 0 || !track.triangulated) return;
  std::size_t run = 0;  // the newest measurements, all beyond the bound
  while (run < norms.size() && norms[norms.size() - 1 - run].second > split_limit) ++run;
  // A tail that misses while an older part (as long as the tail is required to be) still fits: the
  // tracker moved off the point it was triangulated from. A landmark that misses everywhere is left to
  // the RMS test.
  if (run < min_run || norms.size() - run < min_run) return;
  const std::size_t first = norms[norms.size() - run].first;
  const int64_t key = next_split_id_++;
  FeatureTrack& tail = tracks_[key];  // std::map: `track` stays valid
  tail.id = key;
  tail.observations.assign(track.observations.begin() + static_cast<std::ptrdiff_t>(first), track.observations.end());
  track.observations.erase(track.observations.begin() + static_cast<std::ptrdiff_t>(first), track.observations.end());
  norms.resize(norms.size() - run);
  // The features that fed the trajectory (by an alias, or by its own id) extend the new one from now
  // on; the older part is fed no more.
  for (int64_t feature : featuresFeeding(track.id)) split_aliases_[feature] = key;
  tail.feature_ended = track.feature_ended;
  track.feature_ended = true;
  ++stats_.tracks_split;
}

void SlidingWindowEstimator::finish() {
  // Cover the stream's tail with the knots still missing, and solve once more.
  if (tracking_ && last_event_ns_ > trajectory_.newestTime()) {
    while (last_event_ns_ > trajectory_.newestTime()) {
      trajectory_.extendTo(trajectory_.newestTime() + knot_dt_ns_);
      ++stats_.knots;
    }
    update(last_event_ns_);
  }
  if (!tracking_) return;
  for (const auto& [t, knot] : trajectory_.knots()) finalizeKnot(knot);
  final_velocity_.flush(final_knots_);
  for (const auto& [id, track] : tracks_) {
    if (track.triangulated) finalizeLandmark(track);
  }
  Segment& segment = stats_.segments.back();
  segment.end = SegmentEnd::kEndOfStream;
  segment.ended_at_ns = last_event_ns_;
  tracking_ = false;
}

void SlidingWindowEstimator::finalizeKnot(const Knot& knot) {
  final_velocity_.push(knot, final_knots_);
  Segment& segment = stats_.segments.back();  // knots are final only inside a segment
  if (segment.knots == 0) segment.t0_ns = knot.t_ns;
  segment.t1_ns = knot.t_ns;
  ++segment.knots;
}

void SlidingWindowEstimator::finalizeLandmark(const FeatureTrack& track) {
  final_landmarks_.push_back({track.id, Eigen::Map<const Eigen::Vector3d>(track.p_w.data()),
                              static_cast<int>(track.observations.size())});
}

std::vector<Knot> SlidingWindowEstimator::takeFinalKnots() { return std::exchange(final_knots_, {}); }
std::vector<UpdateRecord> SlidingWindowEstimator::takeUpdateRecords() { return std::exchange(records_, {}); }
std::vector<LandmarkPoint> SlidingWindowEstimator::takeFinalLandmarks() { return std::exchange(final_landmarks_, {}); }

}  // namespace asynevo::backend
