#include "asynevo/core/config/config.hpp"

#include <gtest/gtest.h>

#include "asynevo/core/error.hpp"

namespace asynevo {
namespace {

TEST(Config, DefaultsAreValid) {
  const Config config;
  EXPECT_NO_THROW(config.validate());
  EXPECT_EQ(config.sensor.width, 240);
  EXPECT_EQ(config.sensor.height, 180);
}

TEST(Config, YamlOverridesOnlyWhatItNames) {
  Config config;
  applyConfigYaml("sensor:\n  width: 346\n  height: 260\n", "test.yaml", config);
  EXPECT_EQ(config.sensor.width, 346);
  EXPECT_EQ(config.sensor.height, 260);
  EXPECT_EQ(config.input.packet_size, Config().input.packet_size);
}

TEST(Config, EmptyYamlChangesNothing) {
  Config config;
  applyConfigYaml("", "empty.yaml", config);
  EXPECT_EQ(configToYaml(config), configToYaml(Config()));
}

TEST(Config, PrintedYamlReadsBackToTheSameConfig) {
  Config config;
  config.sensor.width = 346;
  config.input.max_time_reversal_us = 0.1;
  Config reread;
  applyConfigYaml(configToYaml(config), "printed", reread);
  EXPECT_EQ(configToYaml(reread), configToYaml(config));
  EXPECT_EQ(reread.input.max_time_reversal_us, 0.1);
  EXPECT_EQ(configDigest(reread), configDigest(config));
  EXPECT_NE(configDigest(config), configDigest(Config()));
}

TEST(Config, PrintedYamlDocumentsEveryValue) {
  const std::string yaml = configToYaml(Config());
  EXPECT_NE(yaml.find("width: 240"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("# sensor columns"), std::string::npos) << yaml;
}

void expectInputError(const std::string& yaml, const std::string& expected_what) {
  Config config;
  try {
    applyConfigYaml(yaml, "my.yaml", config);
    FAIL() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), expected_what);
  }
}

TEST(Config, UnknownKeyIsAnErrorWithItsLine) {
  expectInputError("sensor:\n  width: 240\n  hieght: 180\n",
                   "my.yaml:3: unknown configuration key 'sensor.hieght' (known here: height, width)");
  Config config;
  try {
    applyConfigYaml("sensr:\n  width: 240\n", "my.yaml", config);
    FAIL();
  } catch (const InputError& e) {  // the list of sections grows with the modules; check its start and members
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("my.yaml:1: unknown configuration key 'sensr' (known here: ", 0), 0u) << what;
    EXPECT_NE(what.find("sensor"), std::string::npos) << what;
    EXPECT_NE(what.find("input"), std::string::npos) << what;
  }
}

// A YAML complex key ("? " followed by a mapping or list) is not a name: the loader converted every key
// to a string and yaml-cpp's BadConversion escaped as a non-InputError (found 2026-11-26 by the config
// fuzz harness: a stray '?' in config/ecd.yaml's comments).
TEST(Config, KeyThatIsNotANameIsAnErrorWithItsLine) {
  expectInputError("sensor:\n ? # sensor columns\n  min_dt_ms: 0\n",
                   "my.yaml:3: a configuration key in 'sensor' is a mapping, not a name (a stray '?' before it?)");
  expectInputError("? [a, b]\n: 1\n", "my.yaml:1: a configuration key is a list, not a name (a stray '?' before it?)");
}

TEST(Config, WrongTypeIsAnErrorWithItsLine) {
  expectInputError("sensor:\n  width: wide\n", "my.yaml:2: 'sensor.width' must be an integer");
  expectInputError("input:\n  max_time_reversal_us: .nan\n",
                   "my.yaml:2: 'input.max_time_reversal_us' must be a finite number");
  expectInputError("sensor: 3\n", "my.yaml:1: 'sensor' must be a mapping of keys");
}

TEST(Config, MalformedYamlNamesTheLine) {
  Config config;
  try {
    applyConfigYaml("sensor:\n  width: [1, 2\n", "bad.yaml", config);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "bad.yaml");
    EXPECT_NE(std::string(e.what()).find("malformed YAML"), std::string::npos);
  }
}

TEST(Config, OutOfRangeIsAConfigError) {
  Config config;
  EXPECT_THROW(applyConfigYaml("sensor:\n  width: 0\n", "x.yaml", config), ConfigError);
  EXPECT_THROW(applyConfigYaml("input:\n  packet_size: -5\n", "x.yaml", config), ConfigError);
}

TEST(Config, AnUnknownRuleForWeakTwoViewStartsIsRejectedWithItsKey) {
  for (const char* rule : {"keep", "compare", "confirm"}) {
    Config config;
    applyConfigYaml(std::string("backend:\n  init_weak_two_view: ") + rule + "\n", "x.yaml", config);
    EXPECT_EQ(config.backend.init_weak_two_view, rule);
  }
  Config config;
  try {
    applyConfigYaml("backend:\n  init_weak_two_view: always\n", "x.yaml", config);
    FAIL() << "init_weak_two_view: always was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("backend.init_weak_two_view = 'always'"), std::string::npos) << e.what();
  }
}

/// The ConfigError message of applying `yaml` to the defaults, or "accepted".
std::string yamlError(const std::string& yaml) {
  Config config;
  try {
    applyConfigYaml(yaml, "x.yaml", config);
  } catch (const ConfigError& e) {
    return std::string(e.what());
  }
  return std::string("accepted");
}

TEST(Config, TheDepthReversalRuleAndItsMarginAreCheckedWithTheirKeys) {
  for (const char* rule : {"off", "best", "wait"}) {
    Config config;
    applyConfigYaml(std::string("backend:\n  init_depth_reversal: ") + rule + "\n", "x.yaml", config);
    EXPECT_EQ(config.backend.init_depth_reversal, rule);
  }
  EXPECT_NE(yamlError("backend:\n  init_depth_reversal: always\n").find("backend.init_depth_reversal = 'always'"),
            std::string::npos);
  EXPECT_NE(yamlError("backend:\n  init_reversal_margin: 1.5\n").find("backend.init_reversal_margin"), std::string::npos);
}

TEST(Config, TheDirectionAuditKeysAreCheckedWithTheirNames) {
  for (const char* mode : {"off", "log", "restart"}) {
    Config config;
    applyConfigYaml(std::string("backend:\n  direction_audit: ") + mode + "\n", "x.yaml", config);
    EXPECT_EQ(config.backend.direction_audit, mode);
  }
  EXPECT_NE(yamlError("backend:\n  direction_audit: always\n").find("backend.direction_audit = 'always'"),
            std::string::npos);
  EXPECT_NE(yamlError("backend:\n  direction_audit_restart_rule: never\n")
                .find("backend.direction_audit_restart_rule = 'never'"),
            std::string::npos);
  // The span must hold a knot interval; margin in [0, 1]; at least one vote.
  EXPECT_NE(yamlError("backend:\n  direction_audit_span_ms: 10\n").find("backend.direction_audit_span_ms"),
            std::string::npos);
  EXPECT_NE(yamlError("backend:\n  direction_audit_margin: 1.5\n").find("backend.direction_audit_margin"),
            std::string::npos);
  EXPECT_NE(yamlError("backend:\n  direction_audit_votes: 0\n").find("backend.direction_audit_votes"), std::string::npos);
  EXPECT_NE(yamlError("backend:\n  direction_audit_parallax_px: -1\n").find("backend.direction_audit_parallax_px"),
            std::string::npos);
  EXPECT_EQ(yamlError("backend:\n  direction_audit_restart_rule: same\n"), "accepted");
}

TEST(Config, TheTriangulationErrorAndViewsAreCheckedWithTheirNames) {
  for (const char* statistic : {"max", "rms"}) {
    Config config;
    applyConfigYaml(std::string("backend:\n  triangulation_error: ") + statistic + "\n", "x.yaml", config);
    EXPECT_EQ(config.backend.triangulation_error, statistic);
  }
  EXPECT_NE(yamlError("backend:\n  triangulation_error: median\n").find("backend.triangulation_error = 'median'"),
            std::string::npos);
  for (const char* rule : {"all", "solved", "solved_then_all"}) {
    Config config;
    applyConfigYaml(std::string("backend:\n  triangulation_views: ") + rule + "\n", "x.yaml", config);
    EXPECT_EQ(config.backend.triangulation_views, rule);
  }
  EXPECT_NE(yamlError("backend:\n  triangulation_views: newest\n").find("backend.triangulation_views = 'newest'"),
            std::string::npos);
}

TEST(Config, KnotsPerUpdateMustLeaveTheWindowItsLeastKnots) {
  EXPECT_EQ(yamlError("backend:\n  knots_per_update: 2\n"), "accepted");
  EXPECT_NE(yamlError("backend:\n  knots_per_update: 0\n").find("backend.knots_per_update = 0"), std::string::npos);
  // More new knots per update than window_min_knots - 1 (8 - 1 by default) would outgrow the least window.
  EXPECT_NE(yamlError("backend:\n  knots_per_update: 8\n").find("backend.knots_per_update = 8"), std::string::npos);
  EXPECT_EQ(yamlError("backend:\n  window_min_knots: 10\n  knots_per_update: 8\n"), "accepted");
}

TEST(Config, RelinearizeEveryIsAPositiveStepCount) {
  EXPECT_EQ(yamlError("backend:\n  relinearize_every: 2\n"), "accepted");
  EXPECT_NE(yamlError("backend:\n  relinearize_every: 0\n").find("backend.relinearize_every = 0"), std::string::npos);
  EXPECT_NE(yamlError("backend:\n  relinearize_every: 101\n").find("backend.relinearize_every = 101"),
            std::string::npos);
}

TEST(Config, TheSubpixelMethodIsOneOfTwoNames) {
  EXPECT_EQ(yamlError("frontend:\n  neighbour_motion_model: similarity\n"), "accepted");
  EXPECT_EQ(yamlError("frontend:\n  neighbour_motion_model: either\n"), "accepted");
  EXPECT_NE(yamlError("frontend:\n  neighbour_motion_model: affine\n")
                .find("frontend.neighbour_motion_model = 'affine' is not one of translation, similarity, either"),
            std::string::npos);
  EXPECT_EQ(yamlError("frontend:\n  subpixel_method: template_fit\n"), "accepted");
  EXPECT_EQ(yamlError("frontend:\n  subpixel_method: parabola\n"), "accepted");
  EXPECT_NE(yamlError("frontend:\n  subpixel_method: spline\n").find("frontend.subpixel_method = 'spline'"),
            std::string::npos);
}

TEST(Config, AFeatureBudgetLargerThanTheSensorHoldsIsRejectedWithItsKeys) {
  Config config;  // 240x180, border 16 px, features 15 px apart: 208 x 148 px hold 158 hexagonally
  config.validateForSensor();
  config.frontend.max_features = 158;
  config.validateForSensor();
  config.frontend.max_features = 400;
  try {
    config.validateForSensor();
    FAIL() << "a budget of 400 features on 240x180 was accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("frontend.max_features = 400"), std::string::npos) << what;
    EXPECT_NE(what.find("158 features a 240x180 sensor holds"), std::string::npos) << what;
    EXPECT_NE(what.find("frontend.min_distance_px"), std::string::npos) << what;
  }
  // The same budget fits a 1280x720 sensor, and with no minimum distance there is no bound.
  config.sensor.width = 1280;
  config.sensor.height = 720;
  config.validateForSensor();
  config.sensor.width = 240;
  config.sensor.height = 180;
  config.frontend.min_distance_px = 0;
  config.validateForSensor();
  // A border that leaves no image is named.
  config.frontend.border_margin_px = 90;
  EXPECT_THROW(config.validateForSensor(), ConfigError);
}

TEST(Config, TheResolutionRuleScalesDistancesWithTheDiagonal) {
  FrontendConfig f;
  EXPECT_DOUBLE_EQ(f.distanceScale(640, 480), 1.0);  // off by default
  f.scale_distances = true;
  EXPECT_DOUBLE_EQ(f.distanceScale(240, 180), 1.0);
  EXPECT_DOUBLE_EQ(f.distanceScale(640, 480), 800.0 / 300.0);
  EXPECT_NEAR(f.distanceScale(1280, 720), 4.896, 1e-3);
  // The feature-budget check uses the scaled distance: 60 features 15 x 2.67 = 40 px apart fit 640x480
  // (196), 250 do not.
  Config config;
  config.frontend.scale_distances = true;
  config.sensor.width = 640;
  config.sensor.height = 480;
  config.validateForSensor();
  config.frontend.max_features = 250;
  EXPECT_THROW(config.validateForSensor(), ConfigError);
  config.frontend.scale_distances = false;
  config.validateForSensor();
}

TEST(Config, MissingFileIsAnInputError) {
  EXPECT_THROW(loadConfig("/nonexistent/asynevo.yaml"), InputError);
}

}  // namespace
}  // namespace asynevo
