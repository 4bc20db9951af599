#pragma once
// The reader options every command that reads a dataset's events uses (info, run, track, convert): the
// format, the configuration's packet size and time tolerance, and the sensor size by the precedence of
// io/sensor_size.hpp, so all of them read the same folder the same way.

#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"

namespace asynevo {

/// What the command line says about reading the events.
struct DatasetReadSettings {
  std::string format = "auto";  ///< --format
  std::string sensor;           ///< --sensor WxH, "" = not given
  std::string calib;            ///< --calib, "" = the dataset's own calibration
  std::string config_path;      ///< --config, to name it in messages ("" = "the configuration")
  std::string topic;            ///< --topic NAME (ROS bags), "" = the bag's only event topic
  std::string rectify_map;  ///< --rectify-map FILE|none (DSEC), "" = rectify_map.h5 beside the events if any
};

/// Options for openEventReader(files.events, ...). The configuration's sensor size counts only when a
/// file set it (SensorConfig::set_by_file). A malformed --sensor throws ConfigError; `notes` (when given)
/// gets a line for each lower-ranked source naming another size than the one used.
ReaderOptions datasetReaderOptions(const DatasetFiles& files, const Config& config,
                                   const DatasetReadSettings& settings, std::vector<std::string>* notes = nullptr);

}  // namespace asynevo
