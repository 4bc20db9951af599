// Tracking accuracy against exact ground truth on the synthetic stream of bench/frontend (a texture of
// squares translating along a circle): the simulated-sequence criteria, on a short stream.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "../../bench/frontend/synthetic_stream.hpp"
#include "asynevo/frontend/frontend.hpp"

namespace asynevo::frontend {
namespace {

TEST(SyntheticAccuracy, TracksFollowTheExactMotion) {
  const double speed = 500.0;
  const std::vector<Event> events = bench::syntheticStream(240, 180, 0.4, speed);
  Frontend fe(FrontendConfig{}, 240, 180);
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  fe.finish(out);
  std::map<int64_t, std::vector<TrackMeasurement>> tracks;
  for (const auto& m : out.measurements) tracks[m.feature_id].push_back(m);
  std::vector<double> errors;
  int long_lived_bad = 0;
  for (const auto& [id, ms] : tracks) {
    double ox0, oy0;
    bench::syntheticOffset(speed, ms.front().t_ns * 1e-9, ox0, oy0);
    int64_t first_bad = -1;
    for (const auto& m : ms) {
      double ox, oy;
      bench::syntheticOffset(speed, m.t_ns * 1e-9, ox, oy);
      const double e = std::hypot(m.x - ms.front().x + (ox - ox0), m.y - ms.front().y + (oy - oy0));
      errors.push_back(e);
      if (e > 5 && first_bad < 0) first_bad = m.t_ns;
    }
    if (first_bad >= 0 && ms.back().t_ns - first_bad > 20'000'000) ++long_lived_bad;
  }
  ASSERT_GT(errors.size(), 1000u);
  std::sort(errors.begin(), errors.end());
  EXPECT_LE(errors[errors.size() / 2], 1.0);
  EXPECT_LE(errors[errors.size() * 9 / 10], 2.5);
  EXPECT_LE(long_lived_bad, 1) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_GT(fe.stats().meanActiveFeatures(), 30.0);
}

}  // namespace
}  // namespace asynevo::frontend
