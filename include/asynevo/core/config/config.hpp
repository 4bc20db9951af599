#pragma once
// The whole configuration: one struct per section, every default in code. A YAML file only
// overrides; unknown keys are errors (a typo must not silently fall back to a default).

#include <cstdint>
#include <string>

#include "asynevo/core/config/backend_config.hpp"
#include "asynevo/core/config/frontend_config.hpp"
#include "asynevo/core/config/io_config.hpp"

namespace asynevo {

struct Config {
  SensorConfig sensor;
  InputConfig input;
  FrontendConfig frontend;
  BackendConfig backend;

  template <class V>
  void visit(V& v) {
    v.section("sensor", sensor);
    v.section("input", input);
    v.section("frontend", frontend);
    v.section("backend", backend);
  }
  /// Throws ConfigError naming the first out-of-range value.
  void validate() const;
  /// Checks that need the sensor size, once it is known (the reader's): the border leaves an image and
  /// the feature budget fits it. Throws ConfigError naming the keys.
  void validateForSensor() const;
};

/// Loads `path` over the defaults. Throws InputError (missing/unreadable/malformed file, unknown
/// key, wrong type; with file and line) or ConfigError (value out of range).
Config loadConfig(const std::string& path);
/// Applies YAML text over `config` (same checks as loadConfig; `origin` names the source in errors).
void applyConfigYaml(const std::string& yaml_text, const std::string& origin, Config& config);
/// The effective configuration as YAML, every value, each with its documentation as a comment.
std::string configToYaml(const Config& config);
/// A short stable digest (16 hex digits, FNV-1a 64 of configToYaml) to tell runs' configs apart.
std::string configDigest(const Config& config);

}  // namespace asynevo
