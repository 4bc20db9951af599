// The sensor size: the --sensor text, a folder's sensor.yaml, and the precedence of the sources
// (include/asynevo/io/sensor_size.hpp).
#include "asynevo/io/sensor_size.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

constexpr const char* kCamchain346 =
    "cam0:\n  camera_model: pinhole\n  distortion_model: none\n  intrinsics: [226.4, 226.2, 173.6, 133.7]\n"
    "  resolution: [346, 260]\n";

TEST(SensorSize, ParsesWidthByHeight) {
  const SensorSize size = parseSensorSize("346x260");
  EXPECT_EQ(size.width, 346);
  EXPECT_EQ(size.height, 260);
  EXPECT_EQ(size.origin, "--sensor");
  EXPECT_EQ(parseSensorSize("1280X720").width, 1280);
  EXPECT_EQ(parseSensorSize("1x65535").height, 65535);
}

TEST(SensorSize, MalformedSizesAreRejectedNamingTheFlag) {
  for (const char* bad : {"240", "0x180", "-1x5", "abcxdef", "346x", "x260", "346x260x1", "346 x 260", "+346x260",
                          "65536x10", "346.0x260", ""}) {
    EXPECT_FALSE(tryParseSensorSize(bad)) << bad;
    try {
      parseSensorSize(bad);
      ADD_FAILURE() << "no error for '" << bad << "'";
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("--sensor '") + bad + "' is not WxH, " + kSensorSizeSyntax);
    }
  }
}

TEST(SensorYaml, ReadsWidthAndHeight) {
  TempDir dir;
  const SensorSize size = readSensorYaml(dir.write("sensor.yaml", "# a DAVIS346\nwidth: 346\nheight: 260\n"));
  EXPECT_EQ(size.width, 346);
  EXPECT_EQ(size.height, 260);
  EXPECT_EQ(size.origin, dir.file("sensor.yaml"));
}

TEST(SensorYaml, BadFilesNameTheFileAndLine) {
  struct Case {
    const char* content;
    const char* message;
  };
  const Case cases[] = {
      {"width: 346\n", ":1: no 'height' key: expected two lines 'width: W' and 'height: H'"},
      {"height: 260\n", ":1: no 'width' key"},
      {"width: 346\nheight: big\n", ":2: height must be a whole number of pixels in 1..65535"},
      {"width: 0\nheight: 260\n", ":1: width must be a whole number of pixels in 1..65535"},
      {"width: 346.5\nheight: 260\n", ":1: width must be a whole number of pixels in 1..65535"},
      {"width: 346\nheight: 260\ndepth: 3\n", ":3: unknown key 'depth'"},
      {"width: [346]\nheight: 260\n", ":1: width must be a whole number"},
      {"- 346\n- 260\n", ":1: expected two lines 'width: W' and 'height: H'"},
      {"width: 346\n  height: [\n", ":2: malformed YAML"},
      {"", ": empty file: expected two lines"},
  };
  for (const Case& c : cases) {
    TempDir dir;
    const std::string path = dir.write("sensor.yaml", c.content);
    try {
      readSensorYaml(path);
      ADD_FAILURE() << "no error for:\n" << c.content;
    } catch (const InputError& e) {
      const std::string expected = path + c.message;
      EXPECT_EQ(std::string(e.what()).substr(0, expected.size()), expected) << e.what();
    }
  }
}

// Each source wins over every one below it: --sensor > configuration > sensor.yaml > camchain > format.
TEST(SensorSize, PrecedenceAndNotesAboutOverriddenSizes) {
  TempDir dir;
  dir.write("events.txt", "0.1 1 2 1\n");
  const DatasetFiles bare = resolveDataset(dir.path().string());
  EXPECT_FALSE(chooseSensorSize({}, bare).isSet());  // the format decides

  dir.write("camchain.yaml", kCamchain346);
  const DatasetFiles with_calib = resolveDataset(dir.path().string());
  SensorSize size = chooseSensorSize({}, with_calib);
  EXPECT_EQ(size.width, 346);
  EXPECT_EQ(size.origin, "the calibration " + dir.file("camchain.yaml"));

  dir.write("sensor.yaml", "width: 640\nheight: 480\n");
  const DatasetFiles files = resolveDataset(dir.path().string());
  ASSERT_TRUE(files.sensor);
  std::vector<std::string> notes;
  size = chooseSensorSize({}, files, &notes);
  EXPECT_EQ(size.width, 640);
  EXPECT_EQ(size.origin, dir.file("sensor.yaml"));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "sensor size 640x480 from " + dir.file("sensor.yaml") + " overrides 346x260 from the calibration " +
                          dir.file("camchain.yaml"));

  SensorSizeSources sources;
  sources.config = SensorSize{800, 600, "the configuration c.yaml"};
  EXPECT_EQ(chooseSensorSize(sources, files).width, 800);
  sources.flag = SensorSize{1024, 768, "--sensor"};
  notes.clear();
  size = chooseSensorSize(sources, files, &notes);
  EXPECT_EQ(size.width, 1024);
  EXPECT_EQ(size.height, 768);
  EXPECT_EQ(notes.size(), 3u);  // the configuration, sensor.yaml and the calibration name other sizes

  // An explicit --calib counts as the dataset's calibration.
  std::filesystem::create_directory(dir.file("other"));
  dir.write("other/events.txt", "0.1 1 2 1\n");
  sources = {};
  sources.calib = dir.file("camchain.yaml");
  EXPECT_EQ(chooseSensorSize(sources, resolveDataset(dir.file("other"))).width, 346);
}

// A configuration ranks above the dataset only when its file names a sensor block.
TEST(SensorSize, ConfigurationCountsOnlyWhenItsFileSetsTheSize) {
  TempDir dir;
  dir.write("events.txt", "0.1 1 2 1\n");
  dir.write("sensor.yaml", "width: 640\nheight: 480\n");
  const DatasetFiles files = resolveDataset(dir.path().string());

  Config without_sensor;
  applyConfigYaml("input:\n  packet_size: 1000\n", "c.yaml", without_sensor);
  ReaderOptions options = datasetReaderOptions(files, without_sensor, {});
  EXPECT_EQ(options.width, 640);
  EXPECT_EQ(options.packet_size, 1000);

  Config with_sensor;
  applyConfigYaml("sensor:\n  width: 346\n  height: 260\n", "c.yaml", with_sensor);
  DatasetReadSettings settings;
  settings.config_path = "c.yaml";
  options = datasetReaderOptions(files, with_sensor, settings);
  EXPECT_EQ(options.width, 346);
  EXPECT_EQ(options.size_origin, "the configuration c.yaml");

  settings.sensor = "100x50";
  options = datasetReaderOptions(files, with_sensor, settings);
  EXPECT_EQ(options.width, 100);
  EXPECT_EQ(options.height, 50);
  EXPECT_EQ(options.size_origin, "--sensor");
  settings.sensor = "100";
  EXPECT_THROW(datasetReaderOptions(files, with_sensor, settings), ConfigError);
}

TEST(SensorSize, ConfigurationWithOnlyOneSideIsAnError) {
  Config config;
  try {
    applyConfigYaml("sensor:\n  width: 346\n", "c.yaml", config);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "c.yaml:2: 'sensor' gives only one of width and height: give both, or neither to take the size from "
              "the dataset");
  }
}

}  // namespace
}  // namespace asynevo
