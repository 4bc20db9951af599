// Range checks of the configuration sections. A value out of range is a ConfigError that names the
// key, the value and the allowed range.
#include <fmt/format.h>

#include <cmath>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"

namespace asynevo {

namespace {

template <class T>
void requireRange(const char* key, T value, T lo, T hi) {
  if (!(value >= lo && value <= hi))
    throw ConfigError(fmt::format("configuration value {} = {} is out of range [{}, {}]", key, value, lo, hi));
}

}  // namespace

void SensorConfig::validate() const {
  requireRange("sensor.width", width, 1, 65535);
  requireRange("sensor.height", height, 1, 65535);
}

void InputConfig::validate() const {
  requireRange("input.packet_size", packet_size, 1, 1 << 24);
  requireRange("input.max_time_reversal_us", max_time_reversal_us, 0.0, 1e9);
}

void FrontendConfig::validate() const {
  requireRange("frontend.noise_filter_ms", noise_filter_ms, 0.001, 1e4);
  requireRange("frontend.hot_pixel_window_ms", hot_pixel_window_ms, 1.0, 1e6);
  requireRange("frontend.max_event_rate_mev_s", max_event_rate_mev_s, 0.0, 1e4);
  requireRange("frontend.hot_pixel_factor", hot_pixel_factor, 1.0, 1e6);
  requireRange("frontend.hot_pixel_min_rate_hz", hot_pixel_min_rate_hz, 0.0, 1e7);
  requireRange("frontend.refractory_period_ms", refractory_period_ms, 0.0, 1e6);
  if (neighbour_motion_model != "translation" && neighbour_motion_model != "similarity" &&
      neighbour_motion_model != "either")
    throw ConfigError(fmt::format(
        "configuration value frontend.neighbour_motion_model = '{}' is not one of translation, similarity, either",
        neighbour_motion_model));
  if (subpixel_method != "parabola" && subpixel_method != "template_fit")
    throw ConfigError(fmt::format("configuration value frontend.subpixel_method = '{}' is not one of parabola, template_fit",
                                  subpixel_method));
  if (detector != "fa_harris" && detector != "arc_star")
    throw ConfigError(fmt::format("configuration value frontend.detector = '{}' is not one of fa_harris, arc_star",
                                  detector));
  requireRange("frontend.harris_threshold", harris_threshold, -1e9, 1e9);
  requireRange("frontend.harris_threshold_floor", harris_threshold_floor, 0.05, 1.0);
  if (binning != 0 && binning != 1 && binning != 2 && binning != 4 && binning != 8)
    throw ConfigError(fmt::format("configuration value frontend.binning = {} is not one of 0 (auto), 1, 2, 4, 8",
                                  binning));
  requireRange("frontend.harris_k", harris_k, 0.0, 0.25);
  requireRange("frontend.harris_latest", harris_latest, 1, 81);
  if (tracker != "haste_difference_star" && tracker != "haste_correlation_star")
    throw ConfigError(fmt::format(
        "configuration value frontend.tracker = '{}' is not one of haste_difference_star, haste_correlation_star",
        tracker));
  requireRange("frontend.haste_hysteresis", haste_hysteresis, 0.0, 1.0);
  requireRange("frontend.haste_template_update", haste_template_update, 0.0, 100.0);
  requireRange("frontend.max_features", max_features, 1, 100000);
  requireRange("frontend.min_distance_px", min_distance_px, 0.0, 64.0);
  requireRange("frontend.border_margin_px", border_margin_px, 0.0, 1000.0);
  requireRange("frontend.collision_radius_px", collision_radius_px, 0.0, 8.0);
  requireRange("frontend.min_dt_ms", min_dt_ms, 0.0, 1e6);
  requireRange("frontend.max_idle_ms", max_idle_ms, 0.001, 1e9);
  requireRange("frontend.idle_min_scene_motion_px", idle_min_scene_motion_px, 0.0, 1e6);
  requireRange("frontend.init_timeout_ms", init_timeout_ms, 0.001, 1e9);
  requireRange("frontend.init_timeout_scene_px", init_timeout_scene_px, 0.0, 1e6);
  requireRange("frontend.init_timeout_max_ms", init_timeout_max_ms, init_timeout_ms, 1e9);
  requireRange("frontend.housekeeping_ms", housekeeping_ms, 0.001, 1e6);
  requireRange("frontend.min_anisotropy", min_anisotropy, 0.0, 1.0);
  requireRange("frontend.max_drift_px", max_drift_px, 0.0, 6.0);
  requireRange("frontend.drift_check_ms", drift_check_ms, 0.001, 1e6);
  requireRange("frontend.max_rotation_deg", max_rotation_deg, 0.0, 180.0);
  requireRange("frontend.max_neighbour_disagreement_px", max_neighbour_disagreement_px, 0.0, 1000.0);
  requireRange("frontend.neighbour_disagreement_fraction", neighbour_disagreement_fraction, 0.0, 10.0);
  requireRange("frontend.neighbour_similarity_min_px", neighbour_similarity_min_px, 0.0, 1000.0);
  requireRange("frontend.neighbour_similarity_agreement_px", neighbour_similarity_agreement_px, 0.0, 1000.0);
  requireRange("frontend.neighbour_check_ms", neighbour_check_ms, 0.1, 1e6);
  requireRange("frontend.neighbour_window_ms", neighbour_window_ms, 1.0, 100.0);
  requireRange("frontend.neighbour_count", neighbour_count, 3, 32);
  requireRange("frontend.neighbour_radius_px", neighbour_radius_px, 1.0, 10000.0);
  requireRange("frontend.max_time_reversal_us", max_time_reversal_us, 0.0, 1e9);
}

void BackendConfig::validate() const {
  requireRange("backend.knot_dt_ms", knot_dt_ms, 2.0, 1000.0);
  if (q_c.size() != 6) throw ConfigError("configuration value backend.q_c must have 6 entries");
  for (double q : q_c) requireRange("backend.q_c[i]", q, 1e-12, 1e12);
  requireRange("backend.pixel_sigma", pixel_sigma, 1e-3, 100.0);
  requireRange("backend.huber_px", huber_px, 1e-3, 1000.0);
  requireRange("backend.outlier_px", outlier_px, 1e-3, 1e6);
  requireRange("backend.track_outlier_rms_px", track_outlier_rms_px, 0.0, 1e6);
  requireRange("backend.track_split_px", track_split_px, 0.0, 1e6);
  requireRange("backend.track_split_min_measurements", track_split_min_measurements, 1, 100000);
  requireRange("backend.landmark_rejoin_px", landmark_rejoin_px, 0.0, 1e6);
  requireRange("backend.landmark_rejoin_max_gap_ms", landmark_rejoin_max_gap_ms, 0.0, 1e6);
  requireRange("backend.min_track_measurements", min_track_measurements, 2, 100000);
  requireRange("backend.min_parallax_deg", min_parallax_deg, 0.0, 90.0);
  requireRange("backend.max_triangulation_px", max_triangulation_px, 1e-3, 1e6);
  if (triangulation_error != "max" && triangulation_error != "rms")
    throw ConfigError(fmt::format("configuration value backend.triangulation_error = '{}' is not one of max, rms",
                                  triangulation_error));
  if (triangulation_views != "all" && triangulation_views != "solved" && triangulation_views != "solved_then_all")
    throw ConfigError(fmt::format(
        "configuration value backend.triangulation_views = '{}' is not one of all, solved, solved_then_all",
                                  triangulation_views));
  requireRange("backend.pixel_bounds_focal_px", pixel_bounds_focal_px, 0.0, 1e6);
  requireRange("backend.min_depth", min_depth, 0.0, 1e6);
  if (landmark_depth_range != 0.0)
    requireRange("backend.landmark_depth_range", landmark_depth_range, 1.5, 1e6);
  requireRange("backend.window_min_knots", window_min_knots, 3, 10000);
  requireRange("backend.window_max_knots", window_max_knots, window_min_knots, 10000);
  requireRange("backend.knots_per_update", knots_per_update, 1, window_min_knots - 1);
  requireRange("backend.marginalization_epsilon", marginalization_epsilon, 0.0, 1.0);
  requireRange("backend.scale_anchor_sigma", scale_anchor_sigma, 0.0, 1.0);
  if (forced_marginalization != "fixed_poses" && forced_marginalization != "prior" && forced_marginalization != "drop")
    throw ConfigError(fmt::format(
        "configuration value backend.forced_marginalization = '{}' is not one of fixed_poses, prior, drop",
        forced_marginalization));
  requireRange("backend.max_iterations", max_iterations, 1, 1000);
  requireRange("backend.function_tolerance", function_tolerance, 0.0, 1.0);
  requireRange("backend.initial_trust_region_radius", initial_trust_region_radius, 1e-3, 1e16);
  requireRange("backend.relinearize_every", relinearize_every, 1, 100);
  requireRange("backend.track_measurement_dt_ms", track_measurement_dt_ms, 0.0, 1e4);
  requireRange("backend.max_solver_time_s", max_solver_time_s, 1e-4, 1e4);
  requireRange("backend.solver_threads", solver_threads, 1, 64);
  requireRange("backend.linear_velocity_span_knots", linear_velocity_span_knots, 0, 20);
  if (window_solver != "ceres" && window_solver != "builtin")
    throw ConfigError(
        fmt::format("configuration value backend.window_solver = '{}' is not one of ceres, builtin", window_solver));
  requireRange("backend.init_min_parallax_px", init_min_parallax_px, 0.0, 1e4);
  requireRange("backend.init_min_features", init_min_features, 8, 100000);
  requireRange("backend.init_min_inliers", init_min_inliers, 8, 100000);
  requireRange("backend.init_ransac_px", init_ransac_px, 1e-3, 100.0);
  requireRange("backend.init_window_ms", init_window_ms, 10.0, 1e5);
  requireRange("backend.init_relax_after_ms", init_relax_after_ms, 0.0, 1e9);
  requireRange("backend.init_agreement_deg", init_agreement_deg, 0.0, 180.0);
  requireRange("backend.init_relaxed_fraction", init_relaxed_fraction, 0.1, 1.0);
  if (init_relax_again_after_ms != 0.0)
    requireRange("backend.init_relax_again_after_ms", init_relax_again_after_ms, init_relax_after_ms, 1e9);
  if (init_method != "two-view" && init_method != "multi-view" && init_method != "both")
    throw ConfigError(fmt::format("configuration value backend.init_method = '{}' is not one of two-view, multi-view, both",
                                  init_method));
  if (init_weak_two_view != "keep" && init_weak_two_view != "compare" && init_weak_two_view != "confirm")
    throw ConfigError(fmt::format(
        "configuration value backend.init_weak_two_view = '{}' is not one of keep, compare, confirm", init_weak_two_view));
  if (init_depth_reversal != "off" && init_depth_reversal != "best" && init_depth_reversal != "wait" &&
      init_depth_reversal != "strict")
    throw ConfigError(fmt::format("configuration value backend.init_depth_reversal = '{}' is not one of off, best, wait, strict",
                                  init_depth_reversal));
  requireRange("backend.init_reversal_margin", init_reversal_margin, 0.0, 1.0);
  requireRange("backend.loss_max_event_gap_ms", loss_max_event_gap_ms, 0.0, 1e9);
  if (direction_audit != "off" && direction_audit != "log" && direction_audit != "restart")
    throw ConfigError(fmt::format("configuration value backend.direction_audit = '{}' is not one of off, log, restart",
                                  direction_audit));
  requireRange("backend.direction_audit_ms", direction_audit_ms, 0.0, 1e9);
  requireRange("backend.direction_audit_span_ms", direction_audit_span_ms, knot_dt_ms, 1e9);
  requireRange("backend.direction_audit_margin", direction_audit_margin, 0.0, 1.0);
  requireRange("backend.direction_audit_votes", direction_audit_votes, 1, 1000);
  requireRange("backend.direction_audit_parallax_px", direction_audit_parallax_px, 0.0, 1e6);
  if (direction_audit_restart_rule != "same" && direction_audit_restart_rule != "off" &&
      direction_audit_restart_rule != "best" && direction_audit_restart_rule != "wait" &&
      direction_audit_restart_rule != "strict")
    throw ConfigError(fmt::format(
        "configuration value backend.direction_audit_restart_rule = '{}' is not one of same, off, best, wait, strict",
        direction_audit_restart_rule));
  if (loss_max_event_gap_ms > 0 && loss_max_event_gap_ms < knot_dt_ms)
    throw ConfigError(fmt::format("configuration value backend.loss_max_event_gap_ms = {} must be 0 (off) or at "
                                  "least backend.knot_dt_ms = {}",
                                  loss_max_event_gap_ms, knot_dt_ms));
  requireRange("backend.loss_min_landmarks", loss_min_landmarks, 0, 100000);
  requireRange("backend.loss_unsupported_ms", loss_unsupported_ms, 0.0, 1e9);
  requireRange("backend.loss_max_median_px", loss_max_median_px, 0.0, 1e6);
  if (loss_depth_ratio != 0.0) requireRange("backend.loss_depth_ratio", loss_depth_ratio, 1.5, 1e6);
}

void Config::validate() const {
  sensor.validate();
  input.validate();
  frontend.validate();
  backend.validate();
}

void Config::validateForSensor() const {
  // The feature budget must fit the sensor: features at least min_distance_px apart, inside the border
  // margin, pack at most hexagonally, one per √3/2 · d² of image (Fejes Tóth's circle-packing density).
  const double inner_w = sensor.width - 2.0 * frontend.border_margin_px;
  const double inner_h = sensor.height - 2.0 * frontend.border_margin_px;
  if (inner_w <= 0 || inner_h <= 0)
    throw ConfigError(fmt::format("configuration value frontend.border_margin_px = {} leaves no image inside a {}x{} "
                                  "sensor",
                                  frontend.border_margin_px, sensor.width, sensor.height));
  if (frontend.min_distance_px > 0) {
    const double d = frontend.min_distance_px * frontend.distanceScale(sensor.width, sensor.height);
    const int capacity = static_cast<int>(inner_w * inner_h / (std::sqrt(3.0) / 2.0 * d * d)) + 1;
    if (frontend.max_features > capacity)
      throw ConfigError(fmt::format(
          "configuration value frontend.max_features = {} is more than the {} features a {}x{} sensor holds "
          "{} px apart (frontend.min_distance_px) inside a {} px border (frontend.border_margin_px)",
          frontend.max_features, capacity, sensor.width, sensor.height, d, frontend.border_margin_px));
  }
}

}  // namespace asynevo
