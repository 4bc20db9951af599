#include "asynevo/io/calibration_io.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "asynevo/core/error.hpp"

namespace asynevo {

namespace {

constexpr const char* kEcdLayout = "fx fy cx cy k1 k2 p1 p2 k3";

std::vector<std::string_view> splitWhitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size()) break;
    const std::size_t begin = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

bool isBlankOrComment(std::string_view line) {
  for (char c : line) {
    if (c == '#') return true;
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;
}

/// Locale-independent parse of a whole token. "nan"/"inf" parse (and are rejected by the caller as
/// non-finite, with a clearer message than "not a number").
bool parseDouble(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

/// Builds the model, turning the constructor's std::invalid_argument into an InputError at `line`.
CameraModel makeCamera(const std::string& path, uint64_t line, int width, int height, double fx, double fy,
                       double cx, double cy, DistortionModel model, const std::vector<double>& coefficients) {
  try {
    return CameraModel(width, height, fx, fy, cx, cy, model, coefficients);
  } catch (const std::invalid_argument& e) {
    if (line == 0) throw InputError(path, e.what());
    throw InputError::atLine(path, line, e.what());
  }
}

// ---- Kalibr YAML -----------------------------------------------------------------------------------

uint64_t lineOf(const YAML::Node& node) { return static_cast<uint64_t>(node.Mark().line) + 1; }

std::string scalarOf(const YAML::Node& node) {
  return node.IsScalar() ? node.Scalar() : std::string("<not a scalar>");
}

double yamlNumber(const std::string& path, const YAML::Node& node, const std::string& what) {
  double value = 0;
  if (!node.IsScalar() || !parseDouble(node.Scalar(), value)) {
    // YAML spells NaN and infinity .nan / .inf; yaml-cpp converts those.
    const std::string text = scalarOf(node);
    if (node.IsScalar() && YAML::convert<double>::decode(node, value) && !std::isfinite(value)) {
      throw InputError::atLine(path, lineOf(node), fmt::format("{} '{}' is not finite", what, text));
    }
    throw InputError::atLine(path, lineOf(node), fmt::format("{} '{}' is not a number", what, text));
  }
  if (!std::isfinite(value)) {
    throw InputError::atLine(path, lineOf(node), fmt::format("{} '{}' is not finite", what, node.Scalar()));
  }
  return value;
}

std::vector<double> yamlNumbers(const std::string& path, const YAML::Node& parent, const char* key,
                                std::size_t min_count, std::size_t max_count) {
  const YAML::Node node = parent[key];
  if (!node) throw InputError::atLine(path, lineOf(parent), fmt::format("missing key '{}'", key));
  if (!node.IsSequence()) {
    throw InputError::atLine(path, lineOf(node), fmt::format("'{}' must be a list of numbers", key));
  }
  if (node.size() < min_count || node.size() > max_count) {
    const std::string expected =
        min_count == max_count ? fmt::format("{}", min_count) : fmt::format("{} or {}", min_count, max_count);
    throw InputError::atLine(path, lineOf(node),
                             fmt::format("'{}' needs {} values, found {}", key, expected, node.size()));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(yamlNumber(path, node[i], fmt::format("{}[{}]", key, i)));
  }
  return values;
}

std::string yamlString(const std::string& path, const YAML::Node& parent, const char* key) {
  const YAML::Node node = parent[key];
  if (!node) throw InputError::atLine(path, lineOf(parent), fmt::format("missing key '{}'", key));
  if (!node.IsScalar())
    throw InputError::atLine(path, lineOf(node), fmt::format("'{}' must be a string", key));
  return node.Scalar();
}

std::string formatDouble(double value) {
  // Shortest representation that reads back to the same double.
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(fmt::format("{}: cannot open file for writing", path));
  return out;
}

}  // namespace

CameraModel readEcdCalibration(const std::string& path, int width, int height) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  std::string line;
  uint64_t line_number = 0;
  uint64_t record_line = 0;
  std::vector<double> values;
  while (std::getline(in, line)) {
    ++line_number;
    if (isBlankOrComment(line)) continue;
    if (record_line != 0) {
      throw InputError::atLine(path, line_number,
                               fmt::format("expected a single line ({}), found a second one", kEcdLayout));
    }
    record_line = line_number;
    const std::vector<std::string_view> fields = splitWhitespace(line);
    if (fields.size() != 9) {
      throw InputError::atLine(path, line_number,
                               fmt::format("expected 9 fields ({}), found {}", kEcdLayout, fields.size()));
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      double value = 0;
      if (!parseDouble(fields[k], value)) {
        throw InputError::atLine(path, line_number,
                                 fmt::format("field {} '{}' is not a number", k + 1, fields[k]));
      }
      if (!std::isfinite(value)) {
        throw InputError::atLine(path, line_number,
                                 fmt::format("field {} '{}' is not finite", k + 1, fields[k]));
      }
      values.push_back(value);
    }
  }
  if (record_line == 0) throw InputError(path, fmt::format("empty file: expected one line {}", kEcdLayout));
  return makeCamera(path, record_line, width, height, values[0], values[1], values[2], values[3],
                    DistortionModel::kRadtan, {values[4], values[5], values[6], values[7], values[8]});
}

CameraModel readKalibrCalibration(const std::string& path, const std::string& camera) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(path, "cannot open file");
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError::atLine(path, static_cast<uint64_t>(e.mark.line) + 1, e.msg);
  } catch (const YAML::BadFile&) {
    throw InputError(path, "cannot open file");
  }
  if (!root || root.IsNull()) throw InputError(path, "empty file: expected a Kalibr camchain with " + camera);
  if (!root.IsMap()) throw InputError::atLine(path, lineOf(root), "expected a map of cameras (cam0: ...)");
  const YAML::Node cam = root[camera];
  // DSEC's cam_to_cam.yaml (DSEC README, "Camera Calibration File"): intrinsics: {cam0..cam3, camRect0..camRect3},
  // extrinsics: {...}; not a camchain. Say what to give instead.
  if (!cam && root["intrinsics"] && root["intrinsics"].IsMap() && root["intrinsics"]["camRect0"]) {
    throw InputError::atLine(path, lineOf(root),
                             "this is DSEC's cam_to_cam.yaml, which AsynEVO does not read: for rectified events "
                             "(rectify_map.h5) write camRect0's camera_matrix [fx, fy, cx, cy] (camRect3 for the right "
                             "camera) as a calib.txt 'fx fy cx cy 0 0 0 0 0' (docs/reference/formats.md#rectification)");
  }
  if (!cam) throw InputError::atLine(path, lineOf(root), fmt::format("no camera '{}' in the file", camera));
  if (!cam.IsMap()) throw InputError::atLine(path, lineOf(cam), fmt::format("'{}' must be a map", camera));

  const std::string camera_model = yamlString(path, cam, "camera_model");
  if (camera_model != "pinhole") {
    throw InputError::atLine(path, lineOf(cam["camera_model"]),
                             fmt::format("unsupported camera_model '{}' (supported: pinhole)", camera_model));
  }
  const std::string distortion_name = yamlString(path, cam, "distortion_model");
  DistortionModel model = DistortionModel::kNone;
  std::size_t min_coeffs = 0;
  std::size_t max_coeffs = 0;
  if (distortion_name == "radtan") {
    model = DistortionModel::kRadtan;
    min_coeffs = 4;
    max_coeffs = 5;
  } else if (distortion_name == "equidistant") {
    model = DistortionModel::kEquidistant;
    min_coeffs = max_coeffs = 4;
  } else if (distortion_name != "none") {
    throw InputError::atLine(
        path, lineOf(cam["distortion_model"]),
        fmt::format("unsupported distortion_model '{}' (supported: radtan, equidistant, none)",
                    distortion_name));
  }
  const std::vector<double> intrinsics = yamlNumbers(path, cam, "intrinsics", 4, 4);
  std::vector<double> coefficients;
  if (model != DistortionModel::kNone || cam["distortion_coeffs"]) {
    coefficients = yamlNumbers(path, cam, "distortion_coeffs", min_coeffs, max_coeffs);
  }
  const std::vector<double> resolution = yamlNumbers(path, cam, "resolution", 2, 2);
  for (double r : resolution) {
    if (r != std::floor(r) || r <= 0 || r > 1e6) {
      throw InputError::atLine(
          path, lineOf(cam["resolution"]),
          fmt::format("resolution must be two positive integers, found {}", formatDouble(r)));
    }
  }
  return makeCamera(path, lineOf(cam["intrinsics"]), static_cast<int>(resolution[0]),
                    static_cast<int>(resolution[1]), intrinsics[0], intrinsics[1], intrinsics[2],
                    intrinsics[3], model, coefficients);
}

CameraModel readCalibration(const std::string& path, int width, int height) {
  const auto ends_with = [&](std::string_view suffix) {
    return path.size() >= suffix.size() &&
           path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".yaml") || ends_with(".yml")) return readKalibrCalibration(path);
  return readEcdCalibration(path, width, height);
}

void writeEcdCalibration(const std::string& path, const CameraModel& camera) {
  std::vector<double> c(5, 0.0);
  if (camera.distortionModel() == DistortionModel::kRadtan) {
    c = camera.coefficients();
  } else if (camera.distortionModel() != DistortionModel::kNone) {
    throw Error(fmt::format("{}: the ECD calib.txt format cannot hold a {} camera", path,
                            distortionModelName(camera.distortionModel())));
  }
  std::ofstream out = openForWriting(path);
  out << fmt::format("{} {} {} {} {} {} {} {} {}\n", formatDouble(camera.fx()), formatDouble(camera.fy()),
                     formatDouble(camera.cx()), formatDouble(camera.cy()), formatDouble(c[0]),
                     formatDouble(c[1]), formatDouble(c[2]), formatDouble(c[3]), formatDouble(c[4]));
  if (!out) throw Error(fmt::format("{}: write failed", path));
}

void writeKalibrCalibration(const std::string& path, const CameraModel& camera) {
  std::vector<std::string> coefficients;
  for (double c : camera.coefficients()) coefficients.push_back(formatDouble(c));
  std::ofstream out = openForWriting(path);
  out << "cam0:\n"
      << "  camera_model: pinhole\n"
      << "  distortion_model: " << distortionModelName(camera.distortionModel()) << "\n"
      << "  distortion_coeffs: [" << fmt::format("{}", fmt::join(coefficients, ", ")) << "]\n"
      << "  intrinsics: [" << formatDouble(camera.fx()) << ", " << formatDouble(camera.fy()) << ", "
      << formatDouble(camera.cx()) << ", " << formatDouble(camera.cy()) << "]\n"
      << "  resolution: [" << camera.width() << ", " << camera.height() << "]\n";
  if (!out) throw Error(fmt::format("{}: write failed", path));
}

}  // namespace asynevo
