#include "asynevo/io/dataset_reader.hpp"

#include <cmath>

#include "asynevo/io/sensor_size.hpp"

namespace asynevo {

ReaderOptions datasetReaderOptions(const DatasetFiles& files, const Config& config,
                                   const DatasetReadSettings& settings, std::vector<std::string>* notes) {
  ReaderOptions options;
  options.format = settings.format;
  options.topic = settings.topic;
  options.rectify_map = settings.rectify_map;
  options.packet_size = config.input.packet_size;
  options.max_time_reversal_ns = std::llround(config.input.max_time_reversal_us * 1e3);
  SensorSizeSources sources;
  if (!settings.sensor.empty()) sources.flag = parseSensorSize(settings.sensor, "--sensor");
  if (config.sensor.set_by_file) {
    sources.config = SensorSize{config.sensor.width, config.sensor.height,
                                settings.config_path.empty() ? std::string("the configuration")
                                                             : "the configuration " + settings.config_path};
  }
  sources.calib = settings.calib;
  const SensorSize size = chooseSensorSize(sources, files, notes);
  if (size.isSet()) {
    options.width = size.width;
    options.height = size.height;
    options.size_origin = size.origin;
  }
  return options;
}

}  // namespace asynevo
