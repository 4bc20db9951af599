#pragma once
// The sensor size events are read with, and where it comes from. Event formats differ: ECD text and
// MVSEC HDF5 store no size (their readers assume 240×180 and 346×260), .aevt and most Prophesee RAW/DAT
// headers state it. A size can be given by, highest first (docs/reference/formats.md#sensor-size):
//   1. the --sensor WxH flag,
//   2. a sensor: block in the --config file,
//   3. a sensor.yaml file in the dataset folder ("width: 346" and "height: 260" lines),
//   4. the resolution of a Kalibr camchain in the folder (or given with --calib),
//   5. the event format (its header, or its default).
// A size from 1-4 that differs from the one a file's header states is an error (the reader's).

#include <optional>
#include <string>
#include <vector>

namespace asynevo {

struct DatasetFiles;

struct SensorSize {
  int width = 0;   ///< 0 = not set (the event format decides)
  int height = 0;
  std::string origin;  ///< where it was set, for messages: "--sensor", "the configuration c.yaml", ...

  bool isSet() const { return width > 0 && height > 0; }
};

/// How to set the size, appended to errors about it. (The message texts live in src/, where the docs check
/// looks for them: tests/docs/check_docs.py.)
extern const char* const kSensorSizeHowTo;

/// What a sensor size on the command line looks like, for messages ("the sensor's width and height ...").
extern const char* const kSensorSizeSyntax;

/// Parses "WxH" (e.g. "346x260"; 1..65535 each); nullopt when `text` is anything else.
std::optional<SensorSize> tryParseSensorSize(const std::string& text, const std::string& origin = "--sensor");
/// The same, throwing ConfigError ("--sensor '240' is not WxH, the sensor's ...") for anything else.
SensorSize parseSensorSize(const std::string& text, const std::string& flag = "--sensor");

/// Reads a folder's sensor.yaml: a mapping with exactly the keys width and height, positive integers.
/// Throws InputError naming the file and line.
SensorSize readSensorYaml(const std::string& path);

/// The sources a command has besides the dataset folder.
struct SensorSizeSources {
  std::optional<SensorSize> flag;    ///< --sensor
  std::optional<SensorSize> config;  ///< the configuration's sensor: block, when the file has one
  std::string calib;                 ///< --calib, when given ("" = the folder's calibration)
};

/// The size by precedence (above). Unset (width 0) when nothing but the format gives it. Each
/// lower-ranked source that names another size adds a line to `notes` (when given).
SensorSize chooseSensorSize(const SensorSizeSources& sources, const DatasetFiles& files,
                            std::vector<std::string>* notes = nullptr);

}  // namespace asynevo
