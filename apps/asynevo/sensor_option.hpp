#pragma once
// The --sensor WxH option of the commands that read events (info, run, track, convert): one definition,
// so every command checks and describes it alike. A malformed value is a usage error naming the flag.

#include <CLI/CLI.hpp>

#include <string>

#include "asynevo/io/sensor_size.hpp"

namespace asynevo::cli {

inline CLI::Option* addSensorOption(CLI::App* cmd, std::string& value) {
  const CLI::Validator size_check(
      [](std::string& text) {
        return tryParseSensorSize(text) ? std::string() : "'" + text + "' is not WxH, " + kSensorSizeSyntax;
      },
      "WxH");
  return cmd
      ->add_option("--sensor", value,
                   "sensor size WxH in pixels, e.g. 346x260; overrides the configuration's sensor block, a "
                   "sensor.yaml in the folder, the calibration's resolution and the format's default (a size "
                   "the file's header states must agree)")
      ->check(size_check);
}

}  // namespace asynevo::cli
