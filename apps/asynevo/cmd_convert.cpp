// 'asynevo convert --dataset PATH --out FILE [--out-format auto|aevt|ecd]': read an event file of any
// supported format and write it as AsynEVO's binary format (.aevt, reads >10x faster; a dataset folder with
// events.aevt uses it automatically) or as ECD text (events.txt, t with 9 decimals: lossless).
#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_file.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/event_text.hpp"
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
  std::string rectify_map;
  std::string out;
  std::string out_format = "auto";
};

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// "aevt" or "ecd", from --out-format or else the output file's extension.
std::string outputFormat(const ConvertOptions& options) {
  if (options.out_format == "aevt" || options.out_format == "ecd") return options.out_format;
  if (options.out_format != "auto") {
    throw ConfigError("--out-format: '" + options.out_format + "' is not one of auto, aevt, ecd");
  }
  if (endsWith(options.out, ".aevt")) return "aevt";
  if (endsWith(options.out, ".txt")) return "ecd";
  throw ConfigError("--out " + options.out +
                    ": cannot tell the output format from the file name (.aevt or .txt); give --out-format aevt or ecd");
}

// One of the output formats, behind one interface for the conversion loop.
class ConvertSink {
 public:
  ConvertSink(const std::string& format, const std::string& path, int width, int height) {
    if (format == "aevt") {
      aevt_ = std::make_unique<EventFileWriter>(path, width, height);
    } else {
      text_ = std::make_unique<EventTextWriter>(path);
    }
  }
  void write(const EventPacket& packet) {
    if (aevt_) aevt_->write(packet);
    if (text_) text_->write(packet);
  }
  void close() {
    if (aevt_) aevt_->close();
    if (text_) text_->close();
  }

 private:
  std::unique_ptr<EventFileWriter> aevt_;
  std::unique_ptr<EventTextWriter> text_;
};

void runConvert(const ConvertOptions& options) {
  const std::string out_format = outputFormat(options);
  const Config config = options.config.empty() ? Config() : loadConfig(options.config);
  const DatasetFiles files = resolveDataset(options.dataset, options.format);
  std::vector<std::string> notes;
  const ReaderOptions reader_options = datasetReaderOptions(
      files, config, {options.format, options.sensor, "", options.config, options.topic, options.rectify_map},
      &notes);
  for (const std::string& note : notes) fmt::print("note: {}\n", note);
  auto reader = openEventReader(files.events, reader_options);
  const std::string partial = options.out + ".partial";  // never leave a truncated file under the real name
  ConvertSink writer(out_format, partial, reader->info().width, reader->info().height);
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
  fmt::print("wrote {} events ({}x{}) to {}{}\n", reader->stats().events, reader->info().width, reader->info().height,
             options.out,
             out_format == "ecd" ? " as ECD text (which stores no sensor size: read it back with --sensor or a "
                                   "sensor.yaml unless it is 240x180)"
                                 : "");
  if (!reader->info().rectify_map.empty())
    fmt::print("note: events rectified by {} ({} mapped outside the sensor, dropped)\n",
               reader->info().rectify_map, reader->stats().rectified_outside);
  if (reader->stats().clamped_times > 0)
    fmt::print("note: {} event times went slightly backwards and were clamped\n", reader->stats().clamped_times);
}

}  // namespace

void addConvertCommand(CLI::App& app) {
  static ConvertOptions options;  // CLI11 binds options to stable addresses; one parse per process
  auto* cmd = app.add_subcommand("convert", "Convert an event file to AsynEVO's fast binary format (.aevt) or ECD text");
  cmd->add_option("--dataset", options.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--format", options.format, "input format (auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag, dsec)");
  cmd->add_option("--config", options.config, "configuration YAML (sensor size, time tolerance)");
  addSensorOption(cmd, options.sensor);
  addTopicOption(cmd, options.topic);
  addRectifyMapOption(cmd, options.rectify_map);
  cmd->add_option("--out", options.out, "output file: .aevt (in a dataset folder: events.aevt) or ECD text .txt")
      ->required();
  cmd->add_option("--out-format", options.out_format, "output format: auto (from the --out extension), aevt, ecd")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "aevt", "ecd"}));
  cmd->callback([] { runConvert(options); });
}

}  // namespace asynevo::cli
