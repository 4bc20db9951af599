// The shipped config/*.yaml files load and list every parameter of the configuration.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "asynevo/core/config/config.hpp"
#include "asynevo/sim/sensor.hpp"

namespace asynevo {
namespace {

/// "section.key" of every value line in YAML text written like configToYaml (two-level mapping).
std::set<std::string> keysOf(const std::string& yaml) {
  std::set<std::string> keys;
  std::istringstream in(yaml);
  std::string line, section;
  const std::regex section_re(R"(^([a-z_0-9]+):\s*$)"), key_re(R"(^  ([a-z_0-9]+):\s*\S.*$)");
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, section_re))
      section = m[1];
    else if (std::regex_match(line, m, key_re))
      keys.insert(section + "." + m[1].str());
  }
  return keys;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ConfigFiles, EachLoadsAndListsEveryParameter) {
  const std::set<std::string> all = keysOf(configToYaml(Config()));
  ASSERT_GT(all.size(), 40u);
  for (const char* name : {"ecd", "mvsec", "sim"}) {
    const std::string path = std::string(ASYNEVO_SOURCE_DIR) + "/config/" + name + ".yaml";
    Config config;
    ASSERT_NO_THROW(config = loadConfig(path)) << path;
    const std::set<std::string> listed = keysOf(readFile(path));
    for (const std::string& key : all) EXPECT_EQ(listed.count(key), 1u) << path << " does not list " << key;
    if (std::string(name) == "mvsec") {
      EXPECT_EQ(config.sensor.width, 346);
      EXPECT_EQ(config.sensor.height, 260);
    } else {
      EXPECT_EQ(config.sensor.width, 240);
      EXPECT_EQ(config.sensor.height, 180);
    }
  }
}

// config/sensors/NAME.yaml (tools/sensor_configs.py): for each simulated sensor, the defaults of
// config/sim.yaml with that sensor's size, and nothing else changed.
TEST(ConfigFiles, EachSensorFileIsTheDefaultsAtItsSensorSize) {
  const std::set<std::string> all = keysOf(configToYaml(Config()));
  for (const std::string& name : sim::sensorPresetNames()) {
    const std::string path = std::string(ASYNEVO_SOURCE_DIR) + "/config/sensors/" + name + ".yaml";
    Config config;
    ASSERT_NO_THROW(config = loadConfig(path)) << path;
    const std::set<std::string> listed = keysOf(readFile(path));
    for (const std::string& key : all) EXPECT_EQ(listed.count(key), 1u) << path << " does not list " << key;
    const CameraModel camera = sim::sensorPresetCamera(name);
    EXPECT_EQ(config.sensor.width, camera.width()) << path;
    EXPECT_EQ(config.sensor.height, camera.height()) << path;
    Config expected;
    expected.sensor.width = camera.width();
    expected.sensor.height = camera.height();
    EXPECT_EQ(configToYaml(config), configToYaml(expected)) << path << " differs from the defaults in more than the size";
  }
}

// docs/pipeline.md: without --config the defaults in code are those of config/sim.yaml.
TEST(ConfigFiles, SimFileHoldsTheDefaultsInCode) {
  const std::string path = std::string(ASYNEVO_SOURCE_DIR) + "/config/sim.yaml";
  EXPECT_EQ(configToYaml(loadConfig(path)), configToYaml(Config()));
}

}  // namespace
}  // namespace asynevo
