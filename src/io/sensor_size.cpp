#include "asynevo/io/sensor_size.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <fstream>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"

namespace asynevo {

const char* const kSensorSizeHowTo =
    "set the sensor size with --sensor WxH, a sensor.yaml (width: W, height: H) in the dataset folder or a "
    "sensor: block in the configuration";
const char* const kSensorSizeSyntax = "the sensor's width and height in pixels (1..65535 each), e.g. 346x260";

namespace {

constexpr int kMaxSide = 65535;  // pixel coordinates are 16 bit (core/event.hpp)

/// A whole decimal integer in 1..kMaxSide, or nullopt.
std::optional<int> parseSide(std::string_view text) {
  int value = 0;
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (text.empty() || result.ec != std::errc() || result.ptr != end || value < 1 || value > kMaxSide)
    return std::nullopt;
  return value;
}

uint64_t lineOf(const YAML::Node& node) { return static_cast<uint64_t>(node.Mark().line) + 1; }

}  // namespace

std::optional<SensorSize> tryParseSensorSize(const std::string& text, const std::string& origin) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return std::nullopt;
  const std::optional<int> width = parseSide(std::string_view(text).substr(0, x));
  const std::optional<int> height = parseSide(std::string_view(text).substr(x + 1));
  if (!width || !height) return std::nullopt;
  return SensorSize{*width, *height, origin};
}

SensorSize parseSensorSize(const std::string& text, const std::string& flag) {
  if (std::optional<SensorSize> size = tryParseSensorSize(text, flag)) return *size;
  throw ConfigError(fmt::format("{} '{}' is not WxH, {}", flag, text, kSensorSizeSyntax));
}

SensorSize readSensorYaml(const std::string& path) {
  if (!std::ifstream(path)) throw InputError(path, "cannot open file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError::atLine(path, static_cast<uint64_t>(e.mark.line) + 1, "malformed YAML: " + e.msg);
  }
  constexpr const char* kLayout = "expected two lines 'width: W' and 'height: H' (the sensor size in pixels)";
  if (!root || root.IsNull()) throw InputError(path, std::string("empty file: ") + kLayout);
  if (!root.IsMap()) throw InputError::atLine(path, lineOf(root), kLayout);
  SensorSize size;
  size.origin = path;
  for (const auto& item : root) {
    const std::string key = item.first.Scalar();
    int* side = key == "width" ? &size.width : key == "height" ? &size.height : nullptr;
    if (side == nullptr)
      throw InputError::atLine(path, lineOf(item.first), fmt::format("unknown key '{}': {}", key, kLayout));
    const std::optional<int> value = item.second.IsScalar() ? parseSide(item.second.Scalar()) : std::nullopt;
    if (!value) {
      throw InputError::atLine(path, lineOf(item.second),
                               fmt::format("{} must be a whole number of pixels in 1..{}", key, kMaxSide));
    }
    *side = *value;
  }
  if (!size.isSet())
    throw InputError::atLine(path, lineOf(root), fmt::format("no '{}' key: {}", size.width ? "height" : "width", kLayout));
  return size;
}

SensorSize chooseSensorSize(const SensorSizeSources& sources, const DatasetFiles& files,
                            std::vector<std::string>* notes) {
  std::vector<SensorSize> ranked;  // highest precedence first
  if (sources.flag) ranked.push_back(*sources.flag);
  if (sources.config) ranked.push_back(*sources.config);
  if (files.sensor) ranked.push_back(readSensorYaml(*files.sensor));
  const std::string calib = !sources.calib.empty() ? sources.calib : files.calibration.value_or("");
  if (!calib.empty() && isKalibrCalibration(calib)) {
    const CameraModel camera = readKalibrCalibration(calib);
    ranked.push_back(SensorSize{camera.width(), camera.height(), "the calibration " + calib});
  }
  if (ranked.empty()) return SensorSize{};
  const SensorSize& chosen = ranked.front();
  for (std::size_t i = 1; notes != nullptr && i < ranked.size(); ++i) {
    const SensorSize& other = ranked[i];
    if (other.width != chosen.width || other.height != chosen.height) {
      notes->push_back(fmt::format("sensor size {}x{} from {} overrides {}x{} from {}", chosen.width, chosen.height,
                                   chosen.origin, other.width, other.height, other.origin));
    }
  }
  return chosen;
}

}  // namespace asynevo
