#pragma once
// A sequence of the project simulator (sim module), kept in memory: events plus exact feature ground
// truth. Used by frontend_eval --sim, bench_frontend and the simulated-accuracy tests.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/sim/event_simulator.hpp"
#include "asynevo/sim/feature_ground_truth.hpp"
#include "asynevo/sim/motion.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/sensor.hpp"

namespace asynevo::bench {

struct SimSequence {
  std::string name;
  CameraModel camera = CameraModel::davis240cEcd();
  std::shared_ptr<const sim::Motion> motion;
  std::vector<Event> events;
  std::unique_ptr<sim::FeatureGroundTruth> ground_truth;
};

/// Simulates `motion` over its whole span in a built-in scene (DAVIS240C with the ECD distortion, or the
/// `sensor` preset as below).
inline SimSequence simulateSequence(const std::string& scene, std::shared_ptr<const sim::Motion> motion,
                                    std::string motion_name, uint64_t seed = 1, const std::string& sensor = "") {
  SimSequence s;
  s.name = scene + "/" + motion_name;
  sim::EventSimConfig config;
  if (!sensor.empty()) {
    s.camera = sim::sensorPresetCamera(sensor);
    config.max_pixel_motion = sim::defaultMaxStepMotion(s.camera);
    s.name += " " + sensor;
  }
  s.motion = std::move(motion);
  sim::Scene world = sim::makeBuiltinScene(scene, *s.motion, s.camera, seed);
  sim::EventSimulator simulator(s.camera, world, config, seed);
  simulator.run(*s.motion, s.motion->beginNs(), s.motion->endNs(), [&](const std::vector<Event>& step) {
    s.events.insert(s.events.end(), step.begin(), step.end());
  });
  s.ground_truth = std::make_unique<sim::FeatureGroundTruth>(std::move(world), s.camera, s.motion);
  return s;
}

/// Simulates `duration_s` of a built-in scene and motion preset with the default sensor settings
/// (DAVIS240C with the ECD distortion, as 'asynevo simulate' does). With a `sensor` preset
/// (sim::sensorPresetNames(), e.g. "dvxplorer") that camera is simulated instead, with the render-step
/// bound 'asynevo simulate --sensor' uses.
inline SimSequence simulateSequence(const std::string& scene, const std::string& motion, double duration_s,
                                    uint64_t seed = 1, const std::string& sensor = "") {
  return simulateSequence(scene, sim::makePresetMotion(motion, duration_s), motion, seed, sensor);
}

}  // namespace asynevo::bench
