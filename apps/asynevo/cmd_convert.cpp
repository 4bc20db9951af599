// 'asynevo convert --dataset PATH --out FILE.aevt': parse an event file once and store it in AsynEVO's
// binary format, which reads >10x faster. A dataset folder with events.aevt uses it automatically.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_file.hpp"
#include "asynevo/io/event_reader.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "sensor_option.hpp"

namespace asynevo::cli {

namespace {

struct ConvertOptions {
  std::string dataset;
  std::string format = "auto";
  std::string config;
  std::string sensor;
  std::string topic;
  std::string out;
};

void runConvert(const ConvertOptions& options) {
  const Config config = options.config.empty() ? Config() : loadConfig(options.config);
  const DatasetFiles files = resolveDataset(options.dataset, options.format);
  std::vector<std::string> notes;
  const ReaderOptions reader_options =
      datasetReaderOptions(files, config, {options.format, options.sensor, "", options.config, options.topic}, &notes);
  for (const std::string& note : notes) fmt::print("note: {}\n", note);
  auto reader = openEventReader(files.events, reader_options);
  const std::string partial = options.out + ".partial";  // never leave a truncated file under the real name
  EventFileWriter writer(partial, reader->info().width, reader->info().height);
  Progress progress;
  EventPacket packet;
  int64_t first_t_ns = 0;
  while (reader->read(packet)) {
    if (packet.first_index == 0) first_t_ns = packet.frontTime();
    writer.write(packet);
    progress.update(reader->stats().events, packet.backTime(), first_t_ns);
  }
  progress.finish();
  writer.close();
  if (reader->stats().events == 0) {
    std::remove(partial.c_str());
    throw InputError(reader->info().path, "the file holds no events");
  }
  if (std::rename(partial.c_str(), options.out.c_str()) != 0) throw InputError(options.out, "cannot create the file");
  fmt::print("wrote {} events ({}x{}) to {}\n", reader->stats().events, reader->info().width, reader->info().height,
             options.out);
  if (reader->stats().clamped_times > 0)
    fmt::print("note: {} event times went slightly backwards and were clamped\n", reader->stats().clamped_times);
}

}  // namespace

void addConvertCommand(CLI::App& app) {
  static ConvertOptions options;  // CLI11 binds options to stable addresses; one parse per process
  auto* cmd = app.add_subcommand("convert", "Convert an event file to AsynEVO's fast binary format (.aevt)");
  cmd->add_option("--dataset", options.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--format", options.format, "input format (auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag)");
  cmd->add_option("--config", options.config, "configuration YAML (sensor size, time tolerance)");
  addSensorOption(cmd, options.sensor);
  addTopicOption(cmd, options.topic);
  cmd->add_option("--out", options.out, "output .aevt file (in a dataset folder: events.aevt)")->required();
  cmd->callback([] { runConvert(options); });
}

}  // namespace asynevo::cli
