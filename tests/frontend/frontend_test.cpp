#include "asynevo/frontend/frontend.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "asynevo/core/error.hpp"
#include "synthetic_events.hpp"

namespace asynevo::frontend {
namespace {

using testing::MovingSquare;
using testing::simulateSquares;

Event ev(int64_t t, int x, int y, int p) {
  return Event{t, static_cast<uint16_t>(x), static_cast<uint16_t>(y), static_cast<int8_t>(p)};
}

std::map<int64_t, std::vector<TrackMeasurement>> byFeature(const std::vector<TrackMeasurement>& ms) {
  std::map<int64_t, std::vector<TrackMeasurement>> out;
  for (const auto& m : ms) out[m.feature_id].push_back(m);
  return out;
}

// Two squares, far apart, moving right and down-left: every track follows its square.
void expectTracksOfTheMovingSquares(const FrontendConfig& config) {
  const int w = 160, h = 120;
  const std::vector<MovingSquare> squares = {{30, 30, 30, 120, 40}, {100, 60, 28, -60, 50}};
  const auto events = simulateSquares(squares, w, h, 0.3);
  Frontend fe(config, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  fe.finish(out);
  const FrontendStats& st = fe.stats();
  EXPECT_EQ(st.events, events.size());
  EXPECT_GT(st.features_created, 2u);
  EXPECT_GT(st.measurements, 20u);
  EXPECT_EQ(fe.activeFeatures(), 0);
  uint64_t dropped = 0;
  for (uint64_t d : st.features_dropped) dropped += d;
  EXPECT_EQ(dropped, st.features_created);
  EXPECT_EQ(out.ends.size(), st.features_created);

  // Ids increase with creation; per feature times are non-decreasing and at least min_dt apart.
  const auto tracks = byFeature(out.measurements);
  int64_t previous_first_t = -1;
  for (const auto& [id, ms] : tracks) {
    EXPECT_GE(ms.front().t_ns, previous_first_t - config.init_timeout_ms * 1e6);
    previous_first_t = ms.front().t_ns;
    for (std::size_t i = 1; i < ms.size(); ++i)
      EXPECT_GE(ms[i].t_ns - ms[i - 1].t_ns, static_cast<int64_t>(config.min_dt_ms * 1e6))
          << "feature " << id;
    // Without an undistortion table xn, yn are the raw coordinates.
    EXPECT_EQ(ms.front().xn, ms.front().x);
  }
  // Every track moves with one of the squares: its displacement over its life matches the velocity.
  int matched = 0;
  for (const auto& [id, ms] : tracks) {
    if (ms.size() < 4) continue;
    const double dt = (ms.back().t_ns - ms.front().t_ns) * 1e-9;
    const double dx = ms.back().x - ms.front().x, dy = ms.back().y - ms.front().y;
    double best = 1e9;
    for (const auto& s : squares) best = std::min(best, std::hypot(dx - s.vx * dt, dy - s.vy * dt));
    EXPECT_LT(best, 2.5) << "feature " << id << " over " << dt << " s: moved " << dx << " " << dy << " from "
                         << ms.front().x << " " << ms.front().y << " n " << ms.size();
    ++matched;
  }
  EXPECT_GE(matched, 2);
}

TEST(Frontend, TracksCornersOfMovingSquaresWithThrottledMeasurements) {
  expectTracksOfTheMovingSquares(FrontendConfig{});
}

// The either reference of the neighbour test (docs/method/frontend_quality.md): a feature's neighbours on
// both squares fit a large, meaningless similarity that keeps a track 3.1 px off its square; with the
// agreement bound (2 px) the neighbours, which do not follow that similarity, end it as the translation
// model does.
TEST(Frontend, TheEitherNeighbourReferenceWithAgreementKeepsTheSquaresTracksRight) {
  FrontendConfig config;
  config.neighbour_motion_model = "either";
  config.neighbour_similarity_agreement_px = 2.0;
  expectTracksOfTheMovingSquares(config);
}

// The peak-rate budget (max_event_rate_mev_s): a stream denser than the budget has detections skipped
// and events shed, all counted; tracking goes on; without a budget nothing is.
TEST(Frontend, ThePeakRateBudgetCountsWhatItSkipsAndSheds) {
  const int w = 160, h = 120;
  const std::vector<MovingSquare> squares = {{30, 30, 30, 120, 40}, {100, 60, 28, -60, 50}};
  const auto events = simulateSquares(squares, w, h, 0.3);
  const double rate =
      static_cast<double>(events.size()) / ((events.back().t_ns - events.front().t_ns) * 1e-9);
  auto run = [&](double budget_mev_s) {
    FrontendConfig config;
    config.max_event_rate_mev_s = budget_mev_s;
    Frontend fe(config, w, h);
    MeasurementCollector out;
    for (const Event& e : events) fe.process(e, out);
    fe.finish(out);
    return std::make_pair(fe.stats(), out.measurements.size());
  };
  const auto [plain, plain_measurements] = run(0.0);
  EXPECT_EQ(plain.events_shed, 0u);
  EXPECT_EQ(plain.detections_skipped, 0u);
  const auto [budgeted, budgeted_measurements] = run(rate / 4 * 1e-6);
  EXPECT_EQ(budgeted.events, events.size());
  EXPECT_GT(budgeted.events_shed, 0u);  // only after a window over twice the budget, not after a gap
  EXPECT_GT(budgeted.detections_skipped, 0u);
  EXPECT_LT(budgeted.tracker_updates, plain.tracker_updates);
  EXPECT_GT(budgeted.features_created, 1u);
  EXPECT_GT(budgeted_measurements, 20u);
  FrontendConfig bad;
  bad.max_event_rate_mev_s = -1;
  try {
    bad.validate();
    FAIL() << "a negative budget must be rejected";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("frontend.max_event_rate_mev_s"), std::string::npos) << e.what();
  }
}

// Binning (FrontendConfig::binning): the auto rule, and a 2x2-binned frontend on a scene of twice the
// size tracks like the plain one on the scene itself, with its measurements in sensor pixels.
TEST(Frontend, BinningFollowsTheSensorSizeAndReportsSensorPixels) {
  FrontendConfig automatic;
  automatic.binning = 0;
  EXPECT_EQ(Frontend::binningFor(automatic, 240, 180), 1);
  EXPECT_EQ(Frontend::binningFor(automatic, 346, 260), 1);
  EXPECT_EQ(Frontend::binningFor(automatic, 640, 480), 2);
  EXPECT_EQ(Frontend::binningFor(automatic, 1280, 720), 4);
  FrontendConfig fixed;
  fixed.binning = 2;
  EXPECT_EQ(Frontend::binningFor(fixed, 240, 180), 2);
  fixed.binning = 3;
  EXPECT_THROW(Frontend(fixed, 240, 180), ConfigError);

  const int w = 320, h = 240;
  const std::vector<MovingSquare> squares = {{60, 60, 60, 240, 80}, {200, 120, 56, -120, 100}};
  const auto events = simulateSquares(squares, w, h, 0.3);
  FrontendConfig config;
  config.binning = 2;
  Frontend fe(config, w, h);
  EXPECT_EQ(fe.binning(), 2);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  fe.finish(out);
  EXPECT_EQ(fe.stats().dropped_out_of_sensor, 0u);
  const auto tracks = byFeature(out.measurements);
  int matched = 0;
  for (const auto& [id, ms] : tracks) {
    if (ms.size() < 4) continue;
    for (const TrackMeasurement& m : ms) {
      ASSERT_GE(m.x, 0.f);
      ASSERT_LT(m.x, float(w));
      ASSERT_LT(m.y, float(h));
    }
    // Displacement in sensor pixels: the squares' velocities, not half of them.
    const double dt = (ms.back().t_ns - ms.front().t_ns) * 1e-9;
    const double dx = ms.back().x - ms.front().x, dy = ms.back().y - ms.front().y;
    double best = 1e9;
    for (const auto& s : squares) best = std::min(best, std::hypot(dx - s.vx * dt, dy - s.vy * dt));
    EXPECT_LT(best, 5.0) << "feature " << id << " over " << dt << " s moved " << dx << " " << dy;
    ++matched;
  }
  EXPECT_GE(matched, 2);
  // An event beyond the sensor is dropped, one inside its last bin is not.
  MeasurementCollector none;
  fe.process(ev(400'000'000, w, 0, 1), none);
  fe.process(ev(400'000'000, w - 1, h - 1, 1), none);
  EXPECT_EQ(fe.stats().dropped_out_of_sensor, 1u);
}

TEST(Frontend, FeaturesLeavingTheImageAreDroppedAtTheBorder) {
  const int w = 120, h = 90;
  const std::vector<MovingSquare> squares = {{40, 30, 30, 250, 40}};  // leaves to the right
  const auto events = simulateSquares(squares, w, h, 0.4);
  Frontend fe(FrontendConfig{}, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  EXPECT_GT(fe.stats().features_dropped[static_cast<int>(DropReason::kBorder)], 0u);
  // The border test applies to the tracker state; a measurement adds at most 0.5 px of sub-pixel offset.
  for (const auto& m : out.measurements) {
    EXPECT_GE(m.x, 16.f - 0.5f);
    EXPECT_LE(m.x, w - 1 - 16.f + 0.5f);
  }
}

TEST(Frontend, IdleFeaturesTimeOutWhileTheSceneMovesOn) {
  const int w = 160, h = 120;
  // The first square moves for 0.1 s and then stands still (the same square, static from 0.1 s on: no
  // events where it is), while the second keeps moving: the first square's features stop changing state
  // while the scene moves on, so they end as idle.
  std::vector<MovingSquare> squares = {{30, 30, 30, 100, 60}, {40, 36, 30, 0, 0}, {110, 20, 26, 0, 80}};
  squares[0].t_end = 0.1;
  squares[1].t_start = 0.1;
  const auto events = simulateSquares(squares, w, h, 0.3);
  FrontendConfig config;
  Frontend fe(config, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  EXPECT_GT(fe.stats().features_dropped[static_cast<int>(DropReason::kIdle)], 0u);
  // Nothing measured on the standing square once it stood still.
  for (const auto& m : out.measurements) {
    if (m.t_ns > 100'000'000 + static_cast<int64_t>(config.min_dt_ms * 1e6)) {
      EXPECT_GT(m.x, 90.f) << m.t_ns;
    }
  }
}

TEST(Frontend, ACameraAtRestKeepsItsFeatures) {
  // Two squares move for 0.15 s, everything stands still for 0.3 s (no events at all: no state changes
  // anywhere), then the motion goes on. The features are kept through the pause, and measured again
  // after it under the same ids; with idle_min_scene_motion_px 0 (time alone) they end as idle.
  const int w = 160, h = 120;
  const std::vector<MovingSquare> squares = {{30, 30, 30, 120, 40}, {100, 60, 28, -60, 50}};
  std::vector<Event> events = simulateSquares(squares, w, h, 0.3);
  const int64_t pause_at = 150'000'000, pause = 300'000'000;
  for (Event& e : events) {
    if (e.t_ns >= pause_at) e.t_ns += pause;
  }
  auto run = [&](double idle_min_scene_motion_px, uint64_t& idle_drops) {
    FrontendConfig config;
    config.idle_min_scene_motion_px = idle_min_scene_motion_px;
    Frontend fe(config, w, h);
    MeasurementCollector out;
    for (const Event& e : events) fe.process(e, out);
    idle_drops = fe.stats().features_dropped[static_cast<int>(DropReason::kIdle)];
    std::set<int64_t> before, after;
    for (const auto& m : out.measurements) {
      if (m.t_ns < pause_at) before.insert(m.feature_id);
      if (m.t_ns > pause_at + pause) after.insert(m.feature_id);
    }
    int kept = 0;
    for (const int64_t id : after) kept += before.count(id) > 0;
    return kept;
  };
  uint64_t idle_default = 0, idle_time_alone = 0;
  const int kept_default = run(FrontendConfig{}.idle_min_scene_motion_px, idle_default);
  const int kept_time_alone = run(0, idle_time_alone);
  EXPECT_GE(kept_default, 2) << "features measured before and after the pause";
  EXPECT_EQ(kept_time_alone, 0);
  EXPECT_GT(idle_time_alone, idle_default);
}

/// A slow square (left, 9 px/s) and a fast one (right, 60 px/s) for 0.8 s, run through a frontend with
/// the given start-up time-out settings (without finish(): what the time-out ended is what ended).
MeasurementCollector slowAndFastSquares(double scene_px, double max_ms, FrontendStats& stats) {
  const int w = 160, h = 120;
  static const std::vector<Event> events =
      simulateSquares({{20, 20, 30, 8, 5}, {100, 40, 26, 0, 60}}, w, h, 0.8);
  FrontendConfig config;
  config.init_timeout_scene_px = scene_px;
  config.init_timeout_max_ms = max_ms;
  Frontend fe(config, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  stats = fe.stats();
  return out;
}

// init_timeout_scene_px: a slow square's corners gather their first window over more than
// init_timeout_ms while a fast square moves the scene on. Time alone drops them before their windows
// fill (nothing is measured on the slow square); with a bound on the scene's motion larger than what
// the fast square makes meanwhile they wait, start and are measured; init_timeout_max_ms still ends
// the wait when it is shorter than what they need.
TEST(Frontend, ASlowSceneGivesWeakCornersLongerToStartWhenTheTimeOutFollowsTheMotion) {
  struct Outcome {
    uint64_t timeouts = 0;
    int slow_measurements = 0;
  };
  auto run = [](double scene_px, double max_ms) {
    FrontendStats stats;
    const MeasurementCollector out = slowAndFastSquares(scene_px, max_ms, stats);
    Outcome o;
    o.timeouts = stats.features_dropped[static_cast<int>(DropReason::kInitTimeout)];
    for (const auto& m : out.measurements) o.slow_measurements += m.x < 70.f ? 1 : 0;
    return o;
  };
  const Outcome time_alone = run(0, 500);
  const Outcome motion = run(1000, 700);
  const Outcome capped = run(1000, 150);
  EXPECT_GT(time_alone.timeouts, 0u);
  EXPECT_EQ(time_alone.slow_measurements, 0);
  EXPECT_GT(motion.slow_measurements, 3);
  EXPECT_LT(motion.timeouts, time_alone.timeouts);
  EXPECT_EQ(capped.slow_measurements, 0);
  EXPECT_GT(capped.timeouts, 0u);
}

// A small bound on the scene's motion changes nothing where the scene moves fast: the fast square
// moves that far within init_timeout_ms, so the trackers end as they do with time alone.
TEST(Frontend, AFastSceneDropsTrackersAsTimeAloneWhenTheTimeOutFollowsTheMotion) {
  auto ends = [](double scene_px) {
    FrontendStats stats;
    const MeasurementCollector out =
        slowAndFastSquares(scene_px, FrontendConfig{}.init_timeout_max_ms, stats);
    std::vector<std::pair<int64_t, int64_t>> result;
    for (const FeatureEnd& e : out.ends)
      if (e.reason == DropReason::kInitTimeout) result.emplace_back(e.feature_id, e.t_ns);
    return result;
  };
  const auto time_alone = ends(0);
  EXPECT_FALSE(time_alone.empty());
  EXPECT_EQ(ends(0.5), time_alone);
}

TEST(Frontend, InitTimeOutBoundsAreValidated) {
  FrontendConfig config;
  config.init_timeout_max_ms = config.init_timeout_ms / 2;
  EXPECT_THROW(config.validate(), ConfigError);
  config = FrontendConfig{};
  config.init_timeout_scene_px = -1;
  EXPECT_THROW(config.validate(), ConfigError);
}

TEST(Frontend, BadEventsAreCountedNotProcessed) {
  FrontendConfig config;
  config.max_time_reversal_us = 1.0;
  Frontend fe(config, 50, 40);
  MeasurementCollector out;
  fe.process(ev(1000, 10, 10, 1), out);
  fe.process(ev(2000, 13, 10, 1), out);
  fe.process(ev(2000, 50, 10, 1), out);   // x == width
  fe.process(ev(2000, 10, 40, -1), out);  // y == height
  fe.process(ev(1500, 11, 10, 1), out);   // 500 ns back: clamped
  fe.process(ev(-5000, 12, 10, 1), out);  // far back: dropped
  const FrontendStats& st = fe.stats();
  EXPECT_EQ(st.events, 6u);
  EXPECT_EQ(st.dropped_out_of_sensor, 2u);
  EXPECT_EQ(st.clamped_time, 1u);
  EXPECT_EQ(st.dropped_time_reversal, 1u);
  EXPECT_EQ(fe.sae().latestAt(1, 11, 10), 2000);  // processed at the newest time
  EXPECT_EQ(fe.sae().latestAt(1, 12, 10), kNever);
}

TEST(Frontend, PatchSearchKeepsFeaturesApart) {
  const int w = 160, h = 120;
  // Many small squares close together: features must stay min_distance apart.
  std::vector<MovingSquare> squares;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) squares.push_back({30.0 + 22 * i, 25.0 + 22 * j, 10, 80, 30});
  const auto events = simulateSquares(squares, w, h, 0.1);
  FrontendConfig config;
  Frontend fe(config, w, h);
  MeasurementCollector out;
  double closest = 1e9;
  int64_t max_id = -1;
  for (std::size_t k = 0; k < events.size(); ++k) {
    fe.process(events[k], out);
    if (k % 500 != 0) continue;
    const auto features = fe.features();
    for (std::size_t a = 0; a < features.size(); ++a) {
      max_id = std::max(max_id, features[a].id);
      for (std::size_t b = a + 1; b < features.size(); ++b)
        closest = std::min<double>(closest, std::hypot(features[a].state.x - features[b].state.x,
                                                       features[a].state.y - features[b].state.y));
    }
  }
  EXPECT_GT(fe.stats().features_created, 3u);
  EXPECT_GT(closest, config.collision_radius_px);
  EXPECT_LE(fe.stats().max_active_features, config.max_features);
  EXPECT_EQ(max_id + 1, static_cast<int64_t>(fe.stats().features_created) - 0);
}

/// 20 small squares on a 5 x 4 grid of a 200 x 150 image, all moving alike.
std::vector<MovingSquare> gridOfSquares() {
  std::vector<MovingSquare> squares;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) squares.push_back({25.0 + 32 * i, 22.0 + 28 * j, 12, 60, 20});
  return squares;
}

TEST(Frontend, MaxFeaturesIsRespected) {
  const int w = 200, h = 150;
  const std::vector<MovingSquare> squares = gridOfSquares();
  const auto events = simulateSquares(squares, w, h, 0.06);
  FrontendConfig config;
  config.max_features = 3;
  Frontend fe(config, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  EXPECT_EQ(fe.stats().max_active_features, 3);
}

// The active count's distribution over event time: it covers the stream's span, and its median lies
// between 0 and the most active at once; with a cap of 3 on 20 squares the count sits at the cap.
TEST(Frontend, ActiveFeaturesOverTimeCoverTheSpanAndGiveTheirMedian) {
  const int w = 200, h = 150;
  const std::vector<MovingSquare> squares = gridOfSquares();
  const auto events = simulateSquares(squares, w, h, 0.2);
  FrontendConfig config;
  config.max_features = 3;
  Frontend fe(config, w, h);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  const FrontendStats& st = fe.stats();
  double total = 0;
  for (double sec : st.seconds_at_active_count) total += sec;
  EXPECT_NEAR(total, st.spanSeconds(), 2e-3);  // housekeeping runs every millisecond
  EXPECT_EQ(st.activeFeaturesQuantile(0.5), 3);
  EXPECT_EQ(st.activeFeaturesQuantile(0.0), 0);  // no feature before the first corner
  EXPECT_LE(st.activeFeaturesQuantile(1.0), st.max_active_features);
}

TEST(FrontendStats, ActiveFeaturesQuantileIsTheCountReachedAtThatShareOfTime) {
  FrontendStats st;
  EXPECT_EQ(st.activeFeaturesQuantile(0.5), 0);            // no time yet
  st.seconds_at_active_count = {1.0, 0.0, 0.0, 1.0, 2.0};  // 1 s at 0, 1 s at 3, 2 s at 4
  EXPECT_EQ(st.activeFeaturesQuantile(0.25), 0);
  EXPECT_EQ(st.activeFeaturesQuantile(0.5), 3);
  EXPECT_EQ(st.activeFeaturesQuantile(0.51), 4);
  EXPECT_EQ(st.activeFeaturesQuantile(1.0), 4);
}

TEST(Frontend, UndistortionTableGivesNormalizedCoordinates) {
  UndistortionTable<float> table(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) table.set(x, y, (x - 20) / 100.f, (y - 15) / 100.f, !(x == 0 && y == 0));
  Frontend fe(FrontendConfig{}, 40, 30, table);
  const TrackingFrame& frame = fe.trackingFrame();
  EXPECT_FALSE(frame.rectified());
  float u, v, xn, yn;
  ASSERT_TRUE(frame.measurement(25.5f, 10.25f, u, v, xn, yn));
  EXPECT_EQ(u, 25.5f);
  EXPECT_EQ(v, 10.25f);
  EXPECT_NEAR(xn, 0.055f, 1e-6);
  EXPECT_NEAR(yn, -0.0475f, 1e-6);
  EXPECT_TRUE(frame.measurement(39.f, 29.f, u, v, xn, yn));
  EXPECT_FALSE(frame.measurement(0.5f, 0.5f, u, v, xn, yn));  // touches the invalid entry
  EXPECT_FALSE(frame.measurement(-1.f, 3.f, u, v, xn, yn));
  EXPECT_THROW(Frontend(FrontendConfig{}, 41, 30, table), asynevo::Error);
}

// The neighbour-motion test's parameters are range-checked (docs/frontend.md §Neighbour-motion test).
TEST(Frontend, NeighbourMotionTestParametersAreValidated) {
  FrontendConfig c;
  c.max_neighbour_disagreement_px = 4;
  EXPECT_NO_THROW(Frontend(c, 64, 48));
  auto expectRejected = [&](auto change) {
    FrontendConfig bad = c;
    change(bad);
    EXPECT_THROW(bad.validate(), ConfigError);
  };
  expectRejected([](FrontendConfig& x) { x.neighbour_count = 2; });  // a median of fewer than 3 is not robust
  expectRejected([](FrontendConfig& x) { x.neighbour_window_ms = 500; });  // beyond the remembered history
  expectRejected([](FrontendConfig& x) { x.max_neighbour_disagreement_px = -1; });
  expectRejected([](FrontendConfig& x) { x.neighbour_disagreement_fraction = -0.5; });
  expectRejected([](FrontendConfig& x) { x.neighbour_similarity_agreement_px = -1; });
  expectRejected([](FrontendConfig& x) { x.neighbour_similarity_min_px = -1; });
  expectRejected([](FrontendConfig& x) { x.neighbour_motion_model = "affine"; });
}

}  // namespace
}  // namespace asynevo::frontend
