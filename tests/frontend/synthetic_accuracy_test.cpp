// Tracking accuracy against exact ground truth on the synthetic stream of bench/frontend (a texture of
// squares translating along a circle): the simulated-sequence criteria, on a short stream.
#include <gtest/gtest.h>

#include <vector>

#include "../../bench/frontend/frontend_run.hpp"
#include "asynevo/frontend/frontend.hpp"

namespace asynevo::frontend {
namespace {

TEST(SyntheticAccuracy, TracksFollowTheExactMotion) {
  const double speed = 500.0;
  const std::vector<Event> events = bench::syntheticStream(240, 180, 0.4, speed);
  const bench::FrontendRun run = bench::runFrontend(FrontendConfig{}, events, 240, 180);
  const bench::SyntheticAccuracy r = bench::evaluateSyntheticTracks(run.out.measurements, speed);
  ASSERT_GT(r.errors_px.size(), 1000u);
  EXPECT_LE(bench::SyntheticAccuracy::quantile(r.errors_px, 0.5), 1.0);
  EXPECT_LE(bench::SyntheticAccuracy::quantile(r.errors_px, 0.9), 2.5);
  EXPECT_LE(r.bad_tracks, 1) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_GT(run.stats.meanActiveFeatures(), 30.0);
}

}  // namespace
}  // namespace asynevo::frontend
