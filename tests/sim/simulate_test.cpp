#include "asynevo/sim/simulate.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/lie/so3.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/sensor.hpp"
#include "sim_test_util.hpp"

namespace asynevo::sim {
namespace {

using testing::TempDir;

TEST(SimulateToFolder, WritesAnEcdFolderThatTheReadersLoad) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "shapes";
  spec.motion = "6dof";
  spec.duration_s = 0.4;
  spec.write_binary = true;
  spec.frame_rate_hz = 10;
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_EQ(r.begin_ns, 0);
  EXPECT_EQ(r.end_ns, 400'000'000);
  ASSERT_GT(r.stats.events, 10'000u);

  const std::vector<Event> events = readAllEvents(dir.file("out/events.txt"));
  ASSERT_EQ(events.size(), r.stats.events);
  for (std::size_t i = 1; i < events.size(); ++i) ASSERT_LE(events[i - 1].t_ns, events[i].t_ns);
  const std::vector<Event> binary = readAllEvents(dir.file("out/events.aevt"));
  EXPECT_TRUE(binary == events);

  const CameraModel camera = readEcdCalibration(dir.file("out/calib.txt"));
  EXPECT_EQ(camera.summary(), CameraModel::davis240cEcd().summary());
  EXPECT_EQ(readKalibrCalibration(dir.file("out/camchain.yaml")).summary(), camera.summary());

  // Ground truth at 1 kHz over the whole span, equal to the simulated motion at those times.
  const StampedTrajectory gt = readTumTrajectory(dir.file("out/groundtruth.txt"));
  ASSERT_EQ(gt.size(), 401u);
  EXPECT_EQ(gt.front().t_ns, 0);
  EXPECT_EQ(gt.back().t_ns, 400'000'000);
  const auto motion = makeMotion(spec);
  for (const StampedPose& p : gt) {
    const StampedPose truth = motion->pose(p.t_ns);
    ASSERT_LT((p.p_w_c - truth.p_w_c).norm(), 1e-12);
    ASSERT_LT(lie::so3::log(Eigen::Quaterniond(p.q_w_c.conjugate() * truth.q_w_c)).norm(), 1e-12);
  }
  EXPECT_EQ(r.frames, 5u);  // 0, 0.1, 0.2, 0.3, 0.4 s
  EXPECT_TRUE(std::ifstream(dir.file("out/images/frame_00000004.png")).good());
  EXPECT_TRUE(std::ifstream(dir.file("out/sim.yaml")).good());
}

TEST(SimulateToFolder, SameSeedSameBytes) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "boxes";
  spec.motion = "6dof";
  spec.duration_s = 0.25;
  spec.seed = 42;
  spec.sensor.noise_rate_hz = 0.05;
  simulateToFolder(spec, dir.file("a"));
  simulateToFolder(spec, dir.file("b"));
  spec.seed = 43;
  simulateToFolder(spec, dir.file("c"));
  const std::string a = testing::readBytes(dir.file("a/events.txt"));
  ASSERT_GT(a.size(), 100'000u);
  EXPECT_TRUE(a == testing::readBytes(dir.file("b/events.txt")));
  EXPECT_TRUE(testing::readBytes(dir.file("a/groundtruth.txt")) ==
              testing::readBytes(dir.file("b/groundtruth.txt")));
  EXPECT_FALSE(a == testing::readBytes(dir.file("c/events.txt")));
}

// A motion file without --duration: its whole span (here a 0.5 s TUM file written by the test); with a
// duration: a window from its first pose. The output ground truth is the smoothed motion.
TEST(SimulateToFolder, MotionFileSpanAndGroundTruth) {
  TempDir dir;
  const StampedTrajectory full = readTumTrajectory(testing::dataPath("ecd/shapes_rotation/groundtruth.txt"));
  StampedTrajectory part;
  for (const StampedPose& p : full) {
    if (p.t_ns >= 2'000'000'000 && p.t_ns <= 2'500'000'000) part.push_back(p);
  }
  writeTumTrajectory(dir.file("motion.txt"), part);
  SimulationSpec spec;
  spec.scene = "room";
  spec.motion = dir.file("motion.txt");
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_EQ(r.begin_ns, part.front().t_ns);
  EXPECT_GE(r.end_ns, part.back().t_ns - 5'000'000);  // the spline ends at the last 5 ms grid point
  EXPECT_LE(r.end_ns, part.back().t_ns);
  EXPECT_GT(r.stats.events, 1000u);
  const StampedTrajectory gt = readTumTrajectory(dir.file("out/groundtruth.txt"));
  const auto motion = makeMotion(spec);
  double worst_to_input = 0;
  for (const StampedPose& p : gt) {
    const StampedPose truth = motion->pose(p.t_ns);
    ASSERT_LT((p.p_w_c - truth.p_w_c).norm(), 1e-12);
  }
  for (const StampedPose& p : part) {
    if (p.t_ns > r.end_ns) continue;
    worst_to_input = std::max(worst_to_input, (motion->pose(p.t_ns).p_w_c - p.p_w_c).norm());
  }
  EXPECT_LT(worst_to_input, 0.005);  // the smoothing removes mm-scale mocap noise, not the motion

  spec.duration_s = 0.2;
  const SimulationResult windowed = simulateToFolder(spec, dir.file("windowed"));
  EXPECT_EQ(windowed.begin_ns, part.front().t_ns);
  EXPECT_EQ(windowed.end_ns, part.front().t_ns + 200'000'000);

  spec.start_offset_s = 0.1;
  const auto offset = makeMotion(spec);
  EXPECT_EQ(offset->beginNs(), part.front().t_ns + 100'000'000);
  EXPECT_EQ(offset->endNs(), part.front().t_ns + 300'000'000);
}

TEST(SimulateToFolder, SceneFileWithImageTexture) {
  TempDir dir;
  {
    // A tiny 'poster' image: a PGM that OpenCV reads.
    std::ofstream pgm(dir.file("poster.pgm"), std::ios::binary);
    pgm << "P5\n8 8\n255\n";
    for (int i = 0; i < 64; ++i) pgm.put(static_cast<char>((i * 37) % 256));
  }
  std::ofstream(dir.file("scene.yaml")) << "background: 0.3\n"
                                           "planes:\n"
                                           "  - name: poster\n"
                                           "    center: [0, 0, 1.5]\n"
                                           "    normal: [0, 0, -1]\n"
                                           "    size: [2.0, 2.0]\n"
                                           "    texture: image\n"
                                           "    image: poster.pgm\n"
                                           "  - center: [0.5, 0, 1.0]\n"
                                           "    normal: [0, 0, 1]\n"
                                           "    size: [0.3, 0.3]\n"
                                           "    texture: stripes\n"
                                           "    period: 0.05\n";
  SimulationSpec spec;
  spec.scene = dir.file("scene.yaml");
  spec.motion = "rotation";
  spec.duration_s = 0.2;
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_GT(r.stats.events, 1000u);

  std::ofstream(dir.file("bad.yaml"))
      << "planes:\n  - center: [0, 0]\n    normal: [0, 0, 1]\n    size: [1, 1]\n";
  spec.scene = dir.file("bad.yaml");
  try {
    simulateToFolder(spec, dir.file("bad"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("bad.yaml") + ":2: 'center' must be a list of 3 numbers");
  }
}

TEST(SimulateToFolder, UnknownSceneOrMotionIsAnInputError) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "castle";
  spec.duration_s = 0.1;
  try {
    simulateToFolder(spec, dir.file("out"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "castle: no such scene file (built-in scenes: shapes, checkerboard, stripes, blobs, poster, "
              "boxes, room, photo, photo-room, sparse, grating)");
  }
  spec.scene = "shapes";
  spec.motion = "loop";
  try {
    simulateToFolder(spec, dir.file("out"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "loop: no such motion file (presets: static, rotation, rotation-dominated, translation, 6dof, fast-translation, "
              "slow-start, speed-ramp)");
  }
}

TEST(SimulateToFolder, NoTextNeedsBinaryAndWritesOnlyTheBinaryFile) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "shapes";
  spec.motion = "6dof";
  spec.duration_s = 0.1;
  spec.write_text = false;
  try {
    simulateToFolder(spec, dir.file("out"));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--no-text needs --binary: without events.txt the folder must hold events.aevt");
  }
  spec.write_binary = true;
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/events.txt")));
  EXPECT_EQ(readAllEvents(dir.file("out/events.aevt")).size(), r.stats.events);
  // A second run into the same folder without --binary replaces it: no stale events.aevt is left behind.
  spec.write_binary = false;
  spec.write_text = true;
  simulateToFolder(spec, dir.file("out"));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/events.aevt")));
}

// The noise settings and the count of each noise kind are in sim.yaml.
TEST(SimulateToFolder, SimYamlHoldsTheNoiseSettingsAndCounts) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "shapes";
  spec.motion = "static";
  spec.duration_s = 0.5;
  spec.noise_level = "medium";
  applyNoiseLevel(spec.noise_level, 240, 180, spec.sensor);
  spec.sensor.hot_pixels = 3;
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_GT(r.stats.background_events, 0u);
  EXPECT_GT(r.stats.hot_pixel_events, 0u);
  const std::string yaml = testing::readBytes(dir.file("out/sim.yaml"));
  for (const std::string& line :
       {std::string("  level: \"medium\"\n"), std::string("  background_rate_hz: 0.5\n"),
        std::string("  on_fraction: 0.7\n"), std::string("  hot_pixels: 3\n"), std::string("  hot_pixel_rate_hz: 200\n"),
        std::string("  time_jitter_us: 20\n"), std::string("  contrast_drift: 0.03\n"),
        std::string("  contrast_sigma: 0.05\n"), std::string("sensor_preset: \"davis240c\"\n"),
        "  background_events: " + std::to_string(r.stats.background_events) + "\n",
        "  hot_pixel_events: " + std::to_string(r.stats.hot_pixel_events) + "\n"}) {
    EXPECT_NE(yaml.find(line), std::string::npos) << line << " not in\n" << yaml;
  }
}

// A preset with a start offset through the whole chain: the ground truth is the shifted motion.
TEST(SimulateToFolder, PresetWithStartOffset) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "shapes";
  spec.motion = "6dof";
  spec.duration_s = 0.2;
  spec.start_offset_s = 2.0;
  const SimulationResult r = simulateToFolder(spec, dir.file("out"));
  EXPECT_EQ(r.begin_ns, 0);
  EXPECT_EQ(r.end_ns, 200'000'000);
  EXPECT_GT(r.stats.events, 1000u);
  const StampedTrajectory gt = readTumTrajectory(dir.file("out/groundtruth.txt"));
  const auto shifted = makePresetMotion("6dof", 0.2, 2.0);
  for (const StampedPose& p : gt) ASSERT_LT((p.p_w_c - shifted->pose(p.t_ns).p_w_c).norm(), 1e-12);
  EXPECT_NE(testing::readBytes(dir.file("out/sim.yaml")).find("start_offset_s: 2\n"), std::string::npos);
}

// The photo scenes need Debian's python3-skimage photographs; the error for a missing one names it.
TEST(PhotoScenes, MissingImageNamesTheFileAndThePackage) {
  TempDir dir;
  const char* old = std::getenv("ASYNEVO_IMAGE_DIR");
  const std::string saved = old ? old : "";
  setenv("ASYNEVO_IMAGE_DIR", dir.file("").c_str(), 1);
  const auto motion = makePresetMotion("6dof", 0.5);
  std::string message = "no error";
  try {
    makeBuiltinScene("photo", *motion, CameraModel::davis240cEcd(), 1);
  } catch (const InputError& e) {
    message = e.what();
  }
  if (old) {
    setenv("ASYNEVO_IMAGE_DIR", saved.c_str(), 1);
  } else {
    unsetenv("ASYNEVO_IMAGE_DIR");
  }
  EXPECT_NE(message.find("gravel.png"), std::string::npos) << message;
  EXPECT_NE(message.find("python3-skimage"), std::string::npos) << message;
  EXPECT_NE(message.find("ASYNEVO_IMAGE_DIR"), std::string::npos) << message;
}

TEST(PhotoScenes, PhotoAndPhotoRoomRender) {
  for (const char* file : {"gravel.png", "brick.png", "grass.png", "coffee.png", "camera.png", "astronaut.png"}) {
    if (!std::filesystem::exists(std::filesystem::path(photoDirectory()) / file))
      GTEST_SKIP() << photoDirectory() << "/" << file
                   << " is missing: the photo scenes need Debian's python3-skimage (or ASYNEVO_IMAGE_DIR)";
  }
  TempDir dir;
  for (const char* scene : {"photo", "photo-room"}) {
    SimulationSpec spec;
    spec.scene = scene;
    spec.motion = "6dof";
    spec.duration_s = 0.1;
    const SimulationResult r = simulateToFolder(spec, dir.file(scene));
    std::printf("[ figure ] %s, 0.1 s of 6dof: %llu events; %s\n", scene,
                static_cast<unsigned long long>(r.stats.events), r.scene_description.c_str());
    EXPECT_GT(r.stats.events, 10'000u) << scene;
  }
}

}  // namespace
}  // namespace asynevo::sim
