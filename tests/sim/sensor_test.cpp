#include "asynevo/sim/sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace asynevo::sim {
namespace {

using testing::TempDir;

TEST(SensorPresets, CamerasAndFieldsOfView) {
  struct Expected {
    const char* name;
    int width, height;
    DistortionModel model;
  };
  const Expected expected[] = {{"davis240c", 240, 180, DistortionModel::kRadtan},
                               {"davis346", 346, 260, DistortionModel::kEquidistant},
                               {"dvxplorer", 640, 480, DistortionModel::kRadtan},
                               {"gen4", 1280, 720, DistortionModel::kRadtan}};
  ASSERT_EQ(sensorPresetNames().size(), 4u);
  for (const Expected& e : expected) {
    const CameraModel camera = sensorPresetCamera(e.name);
    EXPECT_EQ(camera.width(), e.width) << e.name;
    EXPECT_EQ(camera.height(), e.height) << e.name;
    EXPECT_EQ(camera.distortionModel(), e.model) << e.name;
    // Horizontal field of view through the left and right image borders (with the distortion).
    const auto left = camera.unprojectBearing(Eigen::Vector2d(-0.5, camera.cy()));
    const auto right = camera.unprojectBearing(Eigen::Vector2d(camera.width() - 0.5, camera.cy()));
    ASSERT_TRUE(left && right) << e.name;
    const double fov_deg = std::acos(left->dot(*right)) * 180.0 / 3.141592653589793;
    std::printf("[ figure ] %s: %s, horizontal field of view %.1f deg, render step bound %.2f px\n", e.name,
                camera.summary().c_str(), fov_deg, defaultMaxStepMotion(camera));
    EXPECT_GT(fov_deg, 55.0) << e.name;
    EXPECT_LT(fov_deg, 95.0) << e.name;
    EXPECT_TRUE(isSensorPreset(e.name));
  }
  EXPECT_EQ(sensorPresetCamera("davis240c").summary(), CameraModel::davis240cEcd().summary());
  EXPECT_EQ(defaultMaxStepMotion(CameraModel::davis240cEcd()), 0.3);  // exactly: today's bytes
  EXPECT_NEAR(defaultMaxStepMotion(sensorPresetCamera("gen4")), 0.3 * 1002.4 / 199.092366542, 1e-12);
  EXPECT_EQ(defaultMaxStepMotion(CameraModel::pinhole(100, 100, 80, 80, 50, 50)), 0.3);
  try {
    sensorPresetCamera("davis640");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "--sensor: unknown sensor 'davis640' (sensors: davis240c, davis346, dvxplorer, gen4)");
  }
}

// Each preset's folder reads back with its own size and camera, the way 'asynevo info' (calibration size)
// and 'asynevo run' (the event file's own size) read it.
TEST(SensorPresets, SimulatedFolderReadsBackWithTheRightSizeAndCamera) {
  TempDir dir;
  for (const std::string& name : sensorPresetNames()) {
    SimulationSpec spec;
    spec.scene = "shapes";
    spec.motion = "6dof";
    spec.duration_s = 0.03;
    spec.sensor_preset = name;
    const std::string out = dir.file(name);
    const SimulationResult r = simulateToFolder(spec, out);
    ASSERT_GT(r.stats.events, 100u) << name;
    const CameraModel camera = sensorPresetCamera(name);
    const bool ecd_size = name == "davis240c";

    const DatasetFiles files = resolveDataset(out);
    ASSERT_TRUE(files.calibration) << name;
    EXPECT_EQ(std::filesystem::path(*files.calibration).filename(), ecd_size ? "calib.txt" : "camchain.yaml")
        << name;
    EXPECT_EQ(std::filesystem::exists(out + "/events.aevt"), !ecd_size) << name;  // no --binary given
    EXPECT_TRUE(std::filesystem::exists(out + "/events.txt")) << name;

    // 'info': the calibration's size for the reader.
    ReaderOptions info_options;
    std::tie(info_options.width, info_options.height) = sensorSizeFromCalibration(files);
    auto reader = openEventReader(files.events, info_options);
    EXPECT_EQ(reader->info().width, camera.width()) << name;
    EXPECT_EQ(reader->info().height, camera.height()) << name;
    // 'run': the event file's own size (no configuration).
    auto run_reader = openEventReader(files.events, ReaderOptions{});
    EXPECT_EQ(run_reader->info().width, camera.width()) << name;
    EXPECT_EQ(run_reader->info().height, camera.height()) << name;
    const std::vector<Event> events = readAllEvents(files.events);
    EXPECT_EQ(events.size(), r.stats.events) << name;

    const CameraModel read = readCalibration(*files.calibration, reader->info().width, reader->info().height);
    EXPECT_EQ(read.summary(), camera.summary()) << name;
    EXPECT_EQ(read.distortionModel(), camera.distortionModel()) << name;
    EXPECT_EQ(readKalibrCalibration(out + "/camchain.yaml").summary(), camera.summary()) << name;
  }
}

TEST(NoiseLevels, SetEveryNoiseSettingAndNoneIsTheDefault) {
  EXPECT_EQ(noiseLevelNames(), (std::vector<std::string>{"none", "low", "medium", "high"}));
  EventSimConfig none;
  none.noise_rate_hz = 3;  // overwritten
  applyNoiseLevel("none", 240, 180, none);
  const EventSimConfig defaults;
  EXPECT_EQ(none.noise_rate_hz, defaults.noise_rate_hz);
  EXPECT_EQ(none.noise_on_fraction, defaults.noise_on_fraction);
  EXPECT_EQ(none.hot_pixels, defaults.hot_pixels);
  EXPECT_EQ(none.hot_pixel_rate_hz, defaults.hot_pixel_rate_hz);
  EXPECT_EQ(none.contrast_sigma, defaults.contrast_sigma);
  EXPECT_EQ(none.contrast_drift, defaults.contrast_drift);
  EXPECT_EQ(none.time_jitter_ns, defaults.time_jitter_ns);

  EventSimConfig low, medium, high;
  applyNoiseLevel("low", 240, 180, low);
  applyNoiseLevel("medium", 240, 180, medium);
  applyNoiseLevel("high", 1280, 720, high);
  EXPECT_EQ(low.noise_rate_hz, 0.1);
  EXPECT_EQ(low.hot_pixels, 1);  // 1e-5 of 43,200 pixels rounds to 0: at least one
  EXPECT_EQ(medium.hot_pixels, 2);
  EXPECT_EQ(high.hot_pixels, 184);  // 2e-4 of 921,600
  EXPECT_EQ(medium.contrast_sigma, 0.05);
  EXPECT_EQ(medium.contrast_drift, 0.03);
  EXPECT_EQ(medium.time_jitter_ns, 20'000);
  EXPECT_EQ(high.noise_rate_hz, 1.5);
  EXPECT_EQ(high.noise_on_fraction, 0.7);
  EXPECT_EQ(high.time_jitter_ns, 100'000);
  EXPECT_EQ(high.contrast, defaults.contrast);  // not a noise setting: untouched
  EXPECT_THROW(applyNoiseLevel("extreme", 240, 180, high), std::invalid_argument);
}

}  // namespace
}  // namespace asynevo::sim
