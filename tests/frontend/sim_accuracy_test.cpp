// Tracking accuracy on sequences of the project simulator against exact feature ground truth
// (sim/feature_ground_truth.hpp): issue 3's simulated-sequence targets, median error <= 1 px and no track
// with error > 5 px surviving more than 20 ms. Short sequences (0.6 s, ~1 s CPU each to simulate).
// Figures for longer sequences and for the scenes where the targets are missed: docs/frontend.md.
#include <gtest/gtest.h>

#include <string>

#include "../../bench/frontend/sim_sequence.hpp"
#include "asynevo/frontend/frontend.hpp"

namespace asynevo::frontend {
namespace {

sim::FeatureAccuracy run(const std::string& scene, const std::string& motion, double seconds, uint64_t seed,
                         const FrontendConfig& config = {}) {
  const bench::SimSequence s = bench::simulateSequence(scene, motion, seconds, seed);
  Frontend fe(config, s.camera.width(), s.camera.height(), s.camera.undistortionTable<float>());
  MeasurementCollector out;
  for (const Event& e : s.events) fe.process(e, out);
  fe.finish(out);
  const sim::FeatureAccuracy r = sim::evaluateFeatureTracks(out.measurements, *s.ground_truth);
  std::printf("%s (%.1f s, seed %llu):\n%s", s.name.c_str(), seconds, static_cast<unsigned long long>(seed),
              r.summary().c_str());
  return r;
}

TEST(SimulatedAccuracy, ShapesSixDofMeetsTheTargets) {
  const sim::FeatureAccuracy r = run("shapes", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 30);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_EQ(r.all.bad_tracks, 0) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_EQ(r.depth_edge_tracks, 0);  // one plane: no depth discontinuity
}

TEST(SimulatedAccuracy, CheckerboardSixDofMeetsTheTargets) {
  const sim::FeatureAccuracy r = run("checkerboard", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 30);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_EQ(r.all.bad_tracks, 0) << "tracks with error > 5 px surviving > 20 ms";
}

// Boxes: cubes before a wall with a smooth multi-scale noise texture ("blobs"). The targets are MISSED
// here (docs/frontend.md): HASTE slides along the soft blob contours, where a corner is not a point.
// This test bounds the current figures so that they do not get worse; tighten it when the tracker or
// its quality test improves.
TEST(SimulatedAccuracy, BoxesSixDofStaysWithinTheMeasuredBounds) {
  const sim::FeatureAccuracy r = run("boxes", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 50);
  EXPECT_LE(r.all.median_px, 1.3);
  EXPECT_LE(r.rigid.median_px, 1.2);
  EXPECT_LE(r.all.bad_tracks, r.all.tracks / 4) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_GT(r.depth_edge_tracks, 0);  // silhouettes against the wall are detected as such
}

}  // namespace
}  // namespace asynevo::frontend
