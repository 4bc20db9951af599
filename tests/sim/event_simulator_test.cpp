#include "asynevo/sim/event_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

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

// What a coarser render step costs: the same step edge at 400 px/s (2 m/s), so the steps are bounded by
// the image motion (0.75 ms at 0.3 px, 3.75 ms at 1.5 px). Event times are compared with the
// box-footprint model above; the error grows with the step, in time and in pixels of travel.
TEST(EventSimulator, CoarserRenderStepsCostTimestampAccuracy) {
  const CameraModel camera = pinhole();
  const Scene scene = stepEdgeScene();
  const double speed_mps = 2.0, start_x = -0.3, px_per_s = 200 * speed_mps / 1.0;
  const AnalyticMotion motion("edge", 0, 200'000'000, [&](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
    p = Eigen::Vector3d(start_x + speed_mps * t, 0, 0);
    q.setIdentity();
  });
  double worst_px[2] = {0, 0};
  const double steps_px[2] = {0.3, 1.5};
  for (int run = 0; run < 2; ++run) {
    EventSimConfig config;
    config.contrast_sigma = 0;
    config.refractory_ns = 0;
    config.max_pixel_motion = steps_px[run];
    EventSimStats stats;
    const std::vector<Event> events = simulate(camera, scene, motion, config, 1, &stats);
    EXPECT_LE(stats.max_step_motion_px, steps_px[run] + 1e-9);
    std::map<std::pair<int, int>, std::vector<int64_t>> per_pixel;
    for (const Event& e : events) per_pixel[{e.x, e.y}].push_back(e.t_ns);
    const double eps = config.log_epsilon;
    for (int y = 0; y < camera.height(); ++y) {
      for (int x = 101; x <= 178; ++x) {
        const std::vector<int64_t>& times = per_pixel[{x, y}];
        ASSERT_EQ(times.size(), 6u) << "pixel " << x << "," << y;
        const double t_x = (179.5 - x) / px_per_s;
        for (std::size_t k = 0; k < times.size(); ++k) {
          const double level = std::exp(std::log(kDark + eps) + static_cast<double>(k + 1) * config.contrast) - eps;
          const double t_model = t_x + ((level - kDark) / (kBright - kDark) - 0.5) / px_per_s;
          worst_px[run] = std::max(worst_px[run], std::fabs(nsToSeconds(times[k]) - t_model) * px_per_s);
        }
      }
    }
    std::printf("[ figure ] step edge at %.0f px/s, step bound %.1f px: %llu steps, worst event-time error %.3f px "
                "of travel (%.3f ms)\n",
                px_per_s, steps_px[run], static_cast<unsigned long long>(stats.render_steps), worst_px[run],
                worst_px[run] / px_per_s * 1e3);
    EXPECT_LE(worst_px[run], steps_px[run] + 0.05);  // within one step's travel
  }
  EXPECT_GT(worst_px[1], worst_px[0]);
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

// Background activity with a polarity bias (DVS leak events are ON): rate and ON share within 5σ.
TEST(EventSimulator, BackgroundNoiseHasTheRequestedRateAndOnShare) {
  const CameraModel camera = pinhole();
  const auto motion = makePresetMotion("static", 2.0);
  const Scene scene = makeBuiltinScene("shapes", *motion, camera, 1);
  EventSimConfig config;
  config.noise_rate_hz = 0.5;
  config.noise_on_fraction = 0.7;
  EventSimStats stats;
  const std::vector<Event> events = simulate(camera, scene, *motion, config, 7, &stats);
  const double expected = 240 * 180 * 0.5 * 2.0;  // 43,200
  EXPECT_NEAR(static_cast<double>(events.size()), expected, 5 * std::sqrt(expected));
  EXPECT_EQ(stats.background_events, events.size());
  EXPECT_EQ(stats.hot_pixel_events, 0u);
  const double n = static_cast<double>(events.size());
  EXPECT_NEAR(static_cast<double>(stats.on_events), 0.7 * n, 5 * std::sqrt(n * 0.7 * 0.3));
  uint64_t on = 0;
  for (const Event& e : events) on += e.polarity > 0 ? 1 : 0;
  EXPECT_EQ(on, stats.on_events);
  std::printf("[ figure ] background 0.5 Hz/px, ON share 0.7: %zu events (expected %.0f), ON share %.4f\n",
              events.size(), expected, static_cast<double>(on) / n);
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

  // With background noise too, and a 250 Hz rate: each kind is counted on its own.
  config.hot_pixels = 4;
  config.hot_pixel_rate_hz = 250;
  config.noise_rate_hz = 0.05;
  config.noise_on_fraction = 0.8;
  EventSimStats stats;
  const std::vector<Event> mixed = simulate(camera, scene, *motion, config, 6, &stats);
  EXPECT_EQ(stats.hot_pixels, 4);
  const double hot_expected = 4 * 250 * 2.0, bg_expected = 240 * 180 * 0.05 * 2.0;
  EXPECT_NEAR(static_cast<double>(stats.hot_pixel_events), hot_expected, 5 * std::sqrt(hot_expected));
  EXPECT_NEAR(static_cast<double>(stats.background_events), bg_expected, 5 * std::sqrt(bg_expected));
  EXPECT_EQ(stats.hot_pixel_events + stats.background_events, mixed.size());
  EXPECT_EQ(stats.noise_events, mixed.size());
  const double n = static_cast<double>(mixed.size());
  EXPECT_NEAR(static_cast<double>(stats.on_events), 0.8 * n, 5 * std::sqrt(n * 0.8 * 0.2));
}

// Timestamp jitter: the same events as without jitter (the jitter has its own random stream), each moved
// by a Gaussian truncated at 3σ, and the output still time-ordered.
TEST(EventSimulator, TimestampJitterKeepsTheOutputSortedWithTheRequestedSpread) {
  const CameraModel camera = pinhole();
  const Scene scene = stepEdgeScene();
  const AnalyticMotion motion("edge", 0, 2'000'000'000, [&](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
    p = Eigen::Vector3d(-0.3 + 0.2 * t, 0, 0);
    q.setIdentity();
  });
  EventSimConfig config;
  config.contrast_sigma = 0;
  config.refractory_ns = 0;
  config.noise_rate_hz = 0.2;  // noise events are jittered too
  EventSimStats plain_stats, jitter_stats;
  const std::vector<Event> plain = simulate(camera, scene, motion, config, 1, &plain_stats);
  config.time_jitter_ns = 100'000;  // σ = 100 µs
  const std::vector<Event> jittered = simulate(camera, scene, motion, config, 1, &jitter_stats);
  ASSERT_EQ(plain.size(), jittered.size());
  ASSERT_GT(plain.size(), 50'000u);
  for (std::size_t i = 1; i < jittered.size(); ++i) {
    const Event& a = jittered[i - 1];
    const Event& b = jittered[i];
    ASSERT_TRUE(a.t_ns < b.t_ns || (a.t_ns == b.t_ns && (a.y < b.y || (a.y == b.y && a.x <= b.x))))
        << "event " << i << " out of order";
    ASSERT_GE(b.t_ns, 0);
    ASSERT_LE(b.t_ns, 2'000'000'000);
  }
  // Pair the events per pixel and polarity in time order (the edge's events of a pixel are >= 2 ms apart,
  // far more than the jitter; noise events are rare enough not to meet them).
  std::map<std::tuple<int, int, int>, std::vector<int64_t>> a, b;
  for (const Event& e : plain) a[{e.x, e.y, e.polarity}].push_back(e.t_ns);
  for (const Event& e : jittered) b[{e.x, e.y, e.polarity}].push_back(e.t_ns);
  ASSERT_EQ(a.size(), b.size());
  double sum = 0, sum2 = 0, worst = 0;
  std::size_t n = 0;
  for (auto& [key, times] : a) {
    std::vector<int64_t>& other = b[key];
    ASSERT_EQ(times.size(), other.size());
    std::sort(other.begin(), other.end());
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (times[k] < 400'000 || times[k] > 1'999'600'000) continue;  // clamped near the ends
      const double d = static_cast<double>(other[k] - times[k]);
      sum += d;
      sum2 += d * d;
      worst = std::max(worst, std::fabs(d));
      ++n;
    }
  }
  const double mean = sum / static_cast<double>(n);
  const double sd = std::sqrt(sum2 / static_cast<double>(n) - mean * mean);
  // A standard normal truncated at ±3 has standard deviation 0.9865.
  std::printf("[ figure ] jitter sigma 100 us: %zu events, mean shift %.2f us, spread %.2f us, worst %.1f us\n", n,
              mean * 1e-3, sd * 1e-3, worst * 1e-3);
  EXPECT_NEAR(sd, 0.9865 * 100'000, 0.03 * 100'000);
  EXPECT_NEAR(mean, 0.0, 5 * 100'000 / std::sqrt(static_cast<double>(n)));
  EXPECT_LE(worst, 300'000 + 1);
}

// The threshold drift: bounded by D, slow, exactly 1 without drift; the event count of the step edge
// follows the drifted threshold at each pixel's crossing time.
TEST(EventSimulator, ContrastDriftIsBoundedSlowAndChangesTheThresholds) {
  const CameraModel camera = pinhole();
  const Scene scene = stepEdgeScene();
  EventSimConfig config;
  EXPECT_EQ(EventSimulator(camera, scene, config, 1).contrastScale(3.7), 1.0);
  config.contrast_drift = 0.2;
  config.contrast_sigma = 0;
  config.refractory_ns = 0;
  const EventSimulator simulator(camera, scene, config, 1);
  double lo = 2, hi = 0, worst_rate = 0;
  for (double t = 0; t <= 120; t += 0.01) {
    const double s = simulator.contrastScale(t);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    worst_rate = std::max(worst_rate, std::fabs(simulator.contrastScale(t + 0.01) - s) / 0.01);
  }
  std::printf("[ figure ] drift D = 0.2 over 120 s: scale %.3f .. %.3f, fastest change %.3f per s\n", lo, hi,
              worst_rate);
  EXPECT_GE(lo, 0.8);
  EXPECT_LE(hi, 1.2);
  EXPECT_GT(hi - lo, 0.1);            // it does drift
  EXPECT_LE(worst_rate, 0.2 * 6.3 / 5);  // periods >= 5 s: |d'| <= D 2π / 5 s

  const AnalyticMotion motion("edge", 0, 2'000'000'000, [&](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
    p = Eigen::Vector3d(-0.3 + 0.2 * t, 0, 0);
    q.setIdentity();
  });
  std::vector<Event> events;
  EventSimulator run_simulator(camera, scene, config, 1);
  run_simulator.run(motion, 0, motion.endNs(),
                    [&](const std::vector<Event>& step) { events.insert(events.end(), step.begin(), step.end()); });
  std::map<std::pair<int, int>, int> count;
  for (const Event& e : events) ++count[{e.x, e.y}];
  const double delta_l = std::log(kBright + config.log_epsilon) - std::log(kDark + config.log_epsilon);
  for (int x = 101; x <= 178; ++x) {
    const double t_x = (179.5 - x) / 40.0;
    // The pixel ramps over ±12.5 ms around t_x; the scale moves by < 0.01 in that time.
    const double s_lo = std::min(simulator.contrastScale(t_x - 0.02), simulator.contrastScale(t_x + 0.02));
    const double s_hi = std::max(simulator.contrastScale(t_x - 0.02), simulator.contrastScale(t_x + 0.02));
    const int most = static_cast<int>(std::floor(delta_l / (config.contrast * s_lo) + 1e-6));
    const int least = static_cast<int>(std::floor(delta_l / (config.contrast * s_hi) - 1e-6));
    for (int y = 0; y < camera.height(); y += 17) {
      const int c = count[{x, y}];
      ASSERT_GE(c, least) << "pixel " << x << "," << y;
      ASSERT_LE(c, most) << "pixel " << x << "," << y;
    }
  }
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
  // Errors name the flag and the value.
  const auto message = [&](const EventSimConfig& c) -> std::string {
    try {
      EventSimulator(camera, scene, c, 1);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  config = EventSimConfig{};
  config.noise_on_fraction = 1.5;
  EXPECT_EQ(message(config), "the ON share of noise events (--noise-on-fraction) must be in [0, 1], got 1.5");
  config = EventSimConfig{};
  config.contrast_drift = 0.6;
  EXPECT_EQ(message(config), "the threshold drift (--contrast-drift) must be in [0, 0.5), got 0.6");
  config = EventSimConfig{};
  config.time_jitter_ns = -1000;
  EXPECT_EQ(message(config), "the timestamp jitter (--time-jitter-us) must not be negative, got -1 us");
  config = EventSimConfig{};
  config.noise_rate_hz = -2;
  EXPECT_EQ(message(config), "the background rate (--noise-rate) must not be negative, got -2");
  config = EventSimConfig{};
  config.refractory_ns = -5000;
  EXPECT_EQ(message(config), "the refractory period (--refractory-us) must not be negative, got -5 us");
}

}  // namespace
}  // namespace asynevo::sim
