#pragma once
// Sensor presets (camera model of a real event camera in one name) and noise levels (all noise settings
// of the event model in one name) for 'asynevo simulate --sensor NAME --noise-level LEVEL'.
// Figures and their sources: docs/simulator.md §Sensors and docs/simulator_noise.md.

#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/sim/event_simulator.hpp"

namespace asynevo::sim {

/// Names of the sensor presets: davis240c (default), davis346, dvxplorer, gen4.
std::vector<std::string> sensorPresetNames();
bool isSensorPreset(const std::string& name);
/// The camera of a preset. Throws std::invalid_argument (naming the value and the presets) otherwise.
CameraModel sensorPresetCamera(const std::string& name);
/// One line on what the preset is and where its figures come from.
std::string sensorPresetDescription(const std::string& name);

/// The render step's image-motion bound for a camera: 0.3 px for the DAVIS240C, scaled with the focal
/// length for longer ones so that a step spans the same angle as on the DAVIS240C:
///   0.3 * max(1, fx / fx_DAVIS240C)   (fx_DAVIS240C = 199.092366542, the ECD calibration).
/// Cameras with fx <= 199.09 keep 0.3 px.
double defaultMaxStepMotion(const CameraModel& camera);

/// Names of the noise levels: none (the defaults of EventSimConfig), low, medium, high.
std::vector<std::string> noiseLevelNames();
bool isNoiseLevel(const std::string& name);
/// Sets the noise fields of `config` (background rate and ON share, hot pixels and their rate, threshold
/// spread and drift, timestamp jitter) for `level` on a width x height sensor (the hot-pixel count is a
/// share of the pixels, at least 1 from 'low' up). Other fields are left alone. Throws
/// std::invalid_argument for an unknown level.
void applyNoiseLevel(const std::string& level, int width, int height, EventSimConfig& config);

}  // namespace asynevo::sim
