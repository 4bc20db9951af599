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

void Config::validate() const {
  sensor.validate();
  input.validate();
}

}  // namespace asynevo
