#include "asynevo/sim/event_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "asynevo/core/time.hpp"

namespace asynevo::sim {
namespace {

CameraModel pinhole() { return CameraModel::pinhole(240, 180, 200, 200, 119.5, 89.5); }

std::vector<Event> simulate(const CameraModel& camera, const Scene& scene, const Motion& motion,
                            const EventSimConfig& config, uint64_t seed, EventSimStats* stats = nullptr) {
  std::vector<Event> events;
  EventSimulator simulator(camera, scene, config, seed);
  const EventSimStats s = simulator.run(
      motion, motion.beginNs(), motion.endNs(),
      [&](const std::vector<Event>& step) { events.insert(events.end(), step.begin(), step.end()); });
  if (stats) *stats = s;
  return events;
}

// A vertical step edge: dark (0.2) for world x < 0, bright (0.8) for x > 0, on a plane at Z = 1 m.
constexpr float kDark = 0.2f, kBright = 0.8f;
Scene stepEdgeScene() {
  std::vector<float> pixels(2048 * 4);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 2048; ++x)
      pixels[static_cast<std::size_t>(y * 2048 + x)] = x < 1024 ? kDark : kBright;
  }
  Scene scene;
  TexturedPlane plane;
  plane.name = "edge";
  plane.center_w = Eigen::Vector3d(0, 0, 1);
  plane.half_width = 2.0;
  plane.half_height = 2.0;
  // 1 mm texels, 2.048 m wide, not repeating (the border rows extend it vertically); the step sits at u = 0.
  plane.texture = std::make_shared<Texture>(pixels, 2048, 4, 0.001, false, "step edge");
  plane.texture_origin_m = Eigen::Vector2d(-1.024, -0.002);
  scene.planes.push_back(plane);
  return scene;
}

// The camera translates along +x at 0.2 m/s, so the edge moves left at f v / Z = 40 px/s, from column
// 179.5 (t = 0) to 99.5 (t = 2 s). Every crossed pixel must fire floor(ΔL / C) ON events (thresholds
// without spread), at the time the edge passes it; every other pixel none.
TEST(EventSimulator, StepEdgeTranslatingAtKnownSpeed) {
  const CameraModel camera = pinhole();
  const Scene scene = stepEdgeScene();
  const double speed_mps = 0.2, start_x = -0.3, px_per_s = 200 * speed_mps / 1.0;
  const AnalyticMotion motion("edge", 0, 2'000'000'000,
                              [&](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
                                p = Eigen::Vector3d(start_x + speed_mps * t, 0, 0);
                                q.setIdentity();
                              });
  EventSimConfig config;
  config.contrast_sigma = 0;
  config.refractory_ns = 0;
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, motion, config, 1, &stats);

  const double delta_l = std::log(kBright + config.log_epsilon) - std::log(kDark + config.log_epsilon);
  const int expected_count = static_cast<int>(std::floor(delta_l / config.contrast));  // 1.35 / 0.2 -> 6
  ASSERT_EQ(expected_count, 6);
  std::map<std::pair<int, int>, std::vector<int64_t>> per_pixel;
  for (const Event& e : events) {
    ASSERT_EQ(e.polarity, 1) << "the edge brightens every pixel it passes";
    per_pixel[{e.x, e.y}].push_back(e.t_ns);
  }
  // The edge crosses pixel column x at t_x = (179.5 - x) / 40 s. While it sweeps over the pixel's
  // footprint (one pixel wide, the renderer's pre-filter), the pixel's intensity ramps linearly from
  // dark to bright, so its k-th event (L = L_dark + k C) comes when the covered fraction reaches
  // F_k = (exp(L_dark + k C) - ε - I_dark) / (I_bright - I_dark):  t_k = t_x + (F_k - 1/2) / (40 px/s).
  const double eps = config.log_epsilon;
  const double step_s = nsToSeconds(stats.max_step_ns);
  double worst_model_s = 0, worst_offset_px = 0, sum_mean_offset = 0;
  int pixels = 0;
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      const auto it = per_pixel.find({x, y});
      const int count = it == per_pixel.end() ? 0 : static_cast<int>(it->second.size());
      if (x >= 101 && x <= 178) {
        ASSERT_EQ(count, expected_count) << "pixel " << x << "," << y;
        const double t_x = (179.5 - x) / px_per_s;
        double mean = 0;
        for (int k = 0; k < count; ++k) {
          const double t = nsToSeconds(it->second[static_cast<std::size_t>(k)]);
          const double level = std::exp(std::log(kDark + eps) + (k + 1) * config.contrast) - eps;
          const double fraction = (level - kDark) / (kBright - kDark);
          const double t_model = t_x + (fraction - 0.5) / px_per_s;
          worst_model_s = std::max(worst_model_s, std::fabs(t - t_model));
          worst_offset_px = std::max(worst_offset_px, std::fabs(t - t_x) * px_per_s);
          ASSERT_LE(std::fabs(t - t_model), step_s) << "pixel " << x << "," << y << " event " << k;
          mean += (t - t_x) / count;
        }
        sum_mean_offset += mean;
        ++pixels;
      } else if (x < 99 || x > 180) {
        ASSERT_EQ(count, 0) << "pixel " << x << "," << y << " is never crossed";
      }
    }
  }
  std::printf(
      "[ figure ] step edge: %zu events, %d per crossed pixel (expected %d); event times vs the "
      "box-footprint model: worst %.3f ms (render step %.2f ms); worst |t - t_cross| %.3f px of travel; "
      "mean offset %.3f ms\n",
      events.size(), expected_count, expected_count, worst_model_s * 1e3, step_s * 1e3, worst_offset_px,
      sum_mean_offset / pixels * 1e3);
}

TEST(EventSimulator, StaticCameraProducesNoEvents) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const auto motion = makePresetMotion("static", 0.5);
  for (const char* name : {"shapes", "boxes", "room"}) {
    const Scene scene = makeBuiltinScene(name, *motion, camera, 3);
    EventSimStats stats;
    const std::vector<Event> events = simulate(camera, scene, *motion, EventSimConfig{}, 3, &stats);
    EXPECT_EQ(events.size(), 0u) << name;
    EXPECT_GT(stats.render_steps, 0u);
  }
}

TEST(EventSimulator, BackgroundNoiseHasTheRequestedRate) {
  const CameraModel camera = pinhole();
  const auto motion = makePresetMotion("static", 2.0);
  const Scene scene = makeBuiltinScene("shapes", *motion, camera, 1);
  EventSimConfig config;
  config.noise_rate_hz = 0.1;  // per pixel: 43,200 px * 0.1 Hz * 2 s = 8,640 expected
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, *motion, config, 5, &stats);
  const double expected = 240 * 180 * 0.1 * 2.0;
  EXPECT_NEAR(static_cast<double>(events.size()), expected, 5 * std::sqrt(expected));
  EXPECT_EQ(stats.noise_events, events.size());
  EXPECT_TRUE(std::is_sorted(events.begin(), events.end(),
                             [](const Event& a, const Event& b) { return a.t_ns < b.t_ns; }));
  int on = 0;
  for (const Event& e : events) on += e.polarity > 0 ? 1 : 0;
  EXPECT_NEAR(on, events.size() / 2.0, 5 * std::sqrt(events.size() / 4.0));
}

TEST(EventSimulator, HotPixelsFireAtTheirRate) {
  const CameraModel camera = pinhole();
  const auto motion = makePresetMotion("static", 2.0);
  const Scene scene = makeBuiltinScene("shapes", *motion, camera, 1);
  EventSimConfig config;
  config.hot_pixels = 3;
  config.hot_pixel_rate_hz = 50;
  const std::vector<Event> events = simulate(camera, scene, *motion, config, 5);
  std::map<std::pair<int, int>, int> per_pixel;
  for (const Event& e : events) ++per_pixel[{e.x, e.y}];
  EXPECT_LE(per_pixel.size(), 3u);
  const double expected = 3 * 50 * 2.0;
  EXPECT_NEAR(static_cast<double>(events.size()), expected, 5 * std::sqrt(expected));
}

// A symmetric texture (checkerboard 0.1/0.9) moved back and forth over whole periods: each pixel ends
// where it started, so ON and OFF events balance.
TEST(EventSimulator, PolarityBalanceForSymmetricTexture) {
  const CameraModel camera = pinhole();
  // Two full periods of a 5 cm side-to-side motion at 2 Hz (peak 0.63 m/s).
  const AnalyticMotion sway("sway", 0, 1'000'000'000,
                            [](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
                              p = Eigen::Vector3d(0.05 * std::sin(2 * 3.141592653589793 * 2 * t), 0, 0);
                              q.setIdentity();
                            });
  const Motion* motion = &sway;
  const Scene scene = makeBuiltinScene("checkerboard", *motion, camera, 1);
  EventSimConfig config;
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, *motion, config, 1, &stats);
  const double imbalance = (static_cast<double>(stats.on_events) - static_cast<double>(stats.off_events)) /
                           static_cast<double>(stats.events);
  std::printf(
      "[ figure ] checkerboard, 2 periods of side-to-side motion: %llu events, ON %llu, OFF %llu, imbalance "
      "%.4f\n",
      static_cast<unsigned long long>(stats.events), static_cast<unsigned long long>(stats.on_events),
      static_cast<unsigned long long>(stats.off_events), imbalance);
  EXPECT_GT(stats.events, 100'000u);
  EXPECT_LT(std::fabs(imbalance), 0.01);
}

TEST(EventSimulator, RefractoryPeriodSeparatesEventsOfAPixel) {
  const CameraModel camera = pinhole();
  const auto motion = makePresetMotion("fast-translation", 0.3);
  const Scene scene = makeBuiltinScene("checkerboard", *motion, camera, 1);
  EventSimConfig config;
  config.refractory_ns = 2'000'000;  // 2 ms, long on purpose
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, *motion, config, 1, &stats);
  EXPECT_GT(stats.refractory_drops, 0u);
  std::map<std::pair<int, int>, int64_t> last;
  for (const Event& e : events) {
    const auto it = last.find({e.x, e.y});
    if (it != last.end()) {
      ASSERT_GE(e.t_ns - it->second, config.refractory_ns);
    }
    last[{e.x, e.y}] = e.t_ns;
  }
}

TEST(EventSimulator, AdaptiveStepsBoundImageMotion) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const auto motion = makePresetMotion("6dof", 1.0);
  const Scene scene = makeBuiltinScene("boxes", *motion, camera, 1);
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, *motion, EventSimConfig{}, 1, &stats);
  EXPECT_LE(stats.max_step_motion_px, 0.3);
  EXPECT_GT(stats.render_steps, 100u);
  EXPECT_GT(events.size(), 10'000u);
  EXPECT_TRUE(std::is_sorted(events.begin(), events.end(),
                             [](const Event& a, const Event& b) { return a.t_ns < b.t_ns; }));
  for (const Event& e : events) {
    ASSERT_LT(e.x, 240);
    ASSERT_LT(e.y, 180);
  }
}

TEST(EventSimulator, ResultDoesNotDependOnThreadsAndFollowsTheSeed) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const auto motion = makePresetMotion("6dof", 0.3);
  const Scene scene = makeBuiltinScene("shapes", *motion, camera, 1);
  EventSimConfig one, two;
  one.threads = 1;
  two.threads = 2;
  one.noise_rate_hz = two.noise_rate_hz = 0.05;
  const std::vector<Event> a = simulate(camera, scene, *motion, one, 9);
  const std::vector<Event> b = simulate(camera, scene, *motion, two, 9);
  const std::vector<Event> c = simulate(camera, scene, *motion, two, 10);
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
}

TEST(EventSimulator, RejectsBadSettings) {
  const CameraModel camera = pinhole();
  const Scene scene = stepEdgeScene();
  EventSimConfig config;
  config.contrast = 0;
  EXPECT_THROW(EventSimulator(camera, scene, config, 1), std::invalid_argument);
  config = EventSimConfig{};
  config.max_pixel_motion = -1;
  EXPECT_THROW(EventSimulator(camera, scene, config, 1), std::invalid_argument);
}

}  // namespace
}  // namespace asynevo::sim
