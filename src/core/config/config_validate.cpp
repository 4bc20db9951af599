// Range checks of the configuration sections. A value out of range is a ConfigError that names the
// key, the value and the allowed range.
#include <fmt/format.h>

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
  requireRange("frontend.refractory_period_ms", refractory_period_ms, 0.0, 1e6);
  if (detector != "fa_harris" && detector != "arc_star")
    throw ConfigError(fmt::format("configuration value frontend.detector = '{}' is not one of fa_harris, arc_star",
                                  detector));
  requireRange("frontend.harris_threshold", harris_threshold, -1e9, 1e9);
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
  requireRange("frontend.init_timeout_ms", init_timeout_ms, 0.001, 1e9);
  requireRange("frontend.housekeeping_ms", housekeeping_ms, 0.001, 1e6);
  requireRange("frontend.min_anisotropy", min_anisotropy, 0.0, 1.0);
  requireRange("frontend.max_time_reversal_us", max_time_reversal_us, 0.0, 1e9);
}

void Config::validate() const {
  sensor.validate();
  input.validate();
  frontend.validate();
}

}  // namespace asynevo
