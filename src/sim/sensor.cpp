#include "asynevo/sim/sensor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace asynevo::sim {

namespace {

// Focal length of the ECD DAVIS240C calibration (CameraModel::davis240cEcd): the reference for the
// render-step bound.
constexpr double kDavis240cFx = 199.092366542;

struct NoiseLevel {
  const char* name;
  double background_hz;      // background events per pixel per second
  double on_fraction;        // share of ON events among background and hot-pixel events
  double hot_pixel_share;    // hot pixels as a share of all pixels (at least 1 when > 0)
  double hot_pixel_rate_hz;  // events per second of each hot pixel
  double contrast_sigma;     // per-pixel threshold spread
  double contrast_drift;     // amplitude of the common-mode threshold drift (relative)
  double time_jitter_us;     // sigma of the timestamp jitter
};

// The table of docs/simulator_noise.md (sources there). 'none' is EventSimConfig's defaults.
constexpr NoiseLevel kNoiseLevels[] = {
    {"none", 0.0, 0.5, 0.0, 50.0, 0.03, 0.0, 0.0},
    {"low", 0.1, 0.7, 1e-5, 100.0, 0.03, 0.0, 0.0},
    {"medium", 0.5, 0.7, 5e-5, 200.0, 0.05, 0.03, 20.0},
    {"high", 1.5, 0.7, 2e-4, 300.0, 0.07, 0.06, 100.0},
};

}  // namespace

std::vector<std::string> sensorPresetNames() { return {"davis240c", "davis346", "dvxplorer", "gen4"}; }

bool isSensorPreset(const std::string& name) {
  const auto names = sensorPresetNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

CameraModel sensorPresetCamera(const std::string& name) {
  if (name == "davis240c") return CameraModel::davis240cEcd();
  if (name == "davis346") {
    // MVSEC indoor_flying, left DAVIS346 (camchain-imucam-indoor_flying.yaml; Zhu et al., "The
    // Multivehicle Stereo Event Camera Dataset", RA-L 2018): pinhole + equidistant.
    return CameraModel(346, 260, 226.38018519795807, 226.15002947047415, 173.6470807871759, 133.73271487507847,
                       DistortionModel::kEquidistant,
                       {-0.048031442223833355, 0.011330957517194437, -0.055378166304281135,
                        0.021500973881459395});
  }
  if (name == "dvxplorer") {
    // DVXplorer-like 640x480: representative figures, not one unit's calibration. fx chosen for a
    // horizontal field of view of 2 atan(320 / 528.7) = 62.4 deg (DAVIS240C: 62.2 deg), principal point a
    // few pixels off the centre, mild barrel distortion.
    return CameraModel(640, 480, 528.7, 529.4, 322.6, 236.9, DistortionModel::kRadtan,
                       {-0.102, 0.052, 3.1e-4, -4.4e-4, 0.0});
  }
  if (name == "gen4") {
    // Prophesee-Gen4-like 1280x720: representative figures, not one unit's calibration. Horizontal field
    // of view 2 atan(640 / 1002.4) = 65.1 deg, mild barrel distortion.
    return CameraModel(1280, 720, 1002.4, 1001.8, 645.3, 356.2, DistortionModel::kRadtan,
                       {-0.081, 0.034, 1.2e-4, -2.6e-4, 0.0});
  }
  throw std::invalid_argument(
      fmt::format("--sensor: unknown sensor '{}' (sensors: {})", name, fmt::join(sensorPresetNames(), ", ")));
}

std::string sensorPresetDescription(const std::string& name) {
  if (name == "davis240c") return "davis240c: ECD DAVIS240C calibration, 240x180, radtan";
  if (name == "davis346") return "davis346: MVSEC indoor_flying left camera, 346x260, equidistant";
  if (name == "dvxplorer") return "dvxplorer: DVXplorer-like 640x480, radtan (representative figures)";
  if (name == "gen4") return "gen4: Prophesee-Gen4-like 1280x720, radtan (representative figures)";
  sensorPresetCamera(name);  // throws the error naming the presets
  return name;
}

double defaultMaxStepMotion(const CameraModel& camera) {
  const double ratio = camera.fx() / kDavis240cFx;  // exactly 1 for the DAVIS240C
  return ratio > 1.0 ? 0.3 * ratio : 0.3;
}

std::vector<std::string> noiseLevelNames() {
  std::vector<std::string> names;
  for (const NoiseLevel& level : kNoiseLevels) names.emplace_back(level.name);
  return names;
}

bool isNoiseLevel(const std::string& name) {
  const auto names = noiseLevelNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void applyNoiseLevel(const std::string& level, int width, int height, EventSimConfig& config) {
  for (const NoiseLevel& l : kNoiseLevels) {
    if (level != l.name) continue;
    config.noise_rate_hz = l.background_hz;
    config.noise_on_fraction = l.on_fraction;
    const double pixels = static_cast<double>(width) * static_cast<double>(height);
    config.hot_pixels =
        l.hot_pixel_share > 0 ? std::max(1, static_cast<int>(std::lround(l.hot_pixel_share * pixels))) : 0;
    config.hot_pixel_rate_hz = l.hot_pixel_rate_hz;
    config.contrast_sigma = l.contrast_sigma;
    config.contrast_drift = l.contrast_drift;
    config.time_jitter_ns = std::llround(l.time_jitter_us * 1e3);
    return;
  }
  throw std::invalid_argument(fmt::format("--noise-level: unknown level '{}' (levels: {})", level,
                                          fmt::join(noiseLevelNames(), ", ")));
}

}  // namespace asynevo::sim
