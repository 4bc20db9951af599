#include "asynevo/sim/motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/lie/so3.hpp"
#include "sim_test_util.hpp"

namespace asynevo::sim {
namespace {

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return lie::so3::log(Eigen::Quaterniond(a.conjugate() * b)).norm();
}

TEST(MotionPresets, EveryPresetIsDefinedAndStartsAtZero) {
  for (const std::string& name : motionPresetNames()) {
    const auto motion = makePresetMotion(name, 3.0);
    EXPECT_EQ(motion->beginNs(), 0);
    EXPECT_EQ(motion->endNs(), 3'000'000'000);
    const StampedPose p = motion->pose(1'234'567'890);
    EXPECT_EQ(p.t_ns, 1'234'567'890);
    EXPECT_NEAR(p.q_w_c.norm(), 1.0, 1e-12);
    EXPECT_TRUE(p.p_w_c.allFinite());
  }
  EXPECT_THROW(makePresetMotion("spiral", 1.0), std::invalid_argument);
  EXPECT_THROW(makePresetMotion("6dof", 0.0), std::invalid_argument);
  EXPECT_FALSE(isMotionPreset("spiral"));
  EXPECT_TRUE(isMotionPreset("6dof"));
}

TEST(MotionPresets, RotationOnlyAndTranslationOnly) {
  const auto rotation = makePresetMotion("rotation", 5.0);
  const auto translation = makePresetMotion("translation", 5.0);
  double max_angle = 0, max_offset = 0;
  for (int64_t t = 0; t <= 5'000'000'000; t += 10'000'000) {
    EXPECT_EQ(rotation->pose(t).p_w_c.norm(), 0.0);
    EXPECT_NEAR(angleBetween(translation->pose(t).q_w_c, Eigen::Quaterniond::Identity()), 0.0, 1e-15);
    max_angle = std::max(max_angle, angleBetween(rotation->pose(t).q_w_c, Eigen::Quaterniond::Identity()));
    max_offset = std::max(max_offset, translation->pose(t).p_w_c.norm());
  }
  EXPECT_GT(max_angle, 0.2);
  EXPECT_GT(max_offset, 0.1);
}

// Without smoothing, the spline through densely sampled smooth poses reproduces them closely (the
// cubic B-spline's approximation error at 5 ms knots is O(Δ² p'') ~ 1e-5 m here).
TEST(SplineMotion, ReproducesASmoothTrajectory) {
  const auto truth = makePresetMotion("6dof", 4.0);
  const StampedTrajectory samples = sampleMotion(*truth, 5'000'000);
  MotionFileOptions options;
  options.cutoff_hz = 0;
  const SplineMotion spline(samples, options, "test");
  EXPECT_EQ(spline.beginNs(), 0);
  EXPECT_EQ(spline.endNs(), 4'000'000'000);
  double worst_p = 0, worst_r = 0;
  for (int64_t t = 0; t <= 4'000'000'000; t += 1'234'567) {
    const StampedPose a = truth->pose(t), b = spline.pose(t);
    worst_p = std::max(worst_p, (a.p_w_c - b.p_w_c).norm());
    worst_r = std::max(worst_r, angleBetween(a.q_w_c, b.q_w_c));
  }
  EXPECT_LT(worst_p, 1e-4);
  EXPECT_LT(worst_r, 1e-4);
  std::printf("[ figure ] spline vs 6dof preset sampled at 5 ms: worst %.2g m, %.2g rad\n", worst_p, worst_r);
}

// Velocity is continuous: finite-difference velocities just before and after a knot agree.
TEST(SplineMotion, VelocityIsContinuousAcrossKnots) {
  const StampedTrajectory samples =
      readTumTrajectory(testing::dataPath("ecd/shapes_rotation/groundtruth.txt"));
  MotionFileOptions options;
  options.end_ns = samples.front().t_ns + 2'000'000'000;
  const SplineMotion spline(samples, options, "test");
  const int64_t h = 1'000;  // 1 µs
  double worst_jump = 0;
  const auto velocity = [&](int64_t t) {
    return Eigen::Vector3d((spline.pose(t + h).p_w_c - spline.pose(t - h).p_w_c) / (2e-9 * h));
  };
  // Knots are at the first sample time + k * 5 ms (the first sample is beginNs() here).
  for (int64_t knot = spline.beginNs() + 50'000'000; knot < spline.endNs() - 50'000'000; knot += 5'000'000) {
    worst_jump = std::max(worst_jump, (velocity(knot - 2 * h) - velocity(knot + 2 * h)).norm());
  }
  EXPECT_LT(worst_jump, 1e-3);  // m/s, across ~4 µs, while the velocity itself is ~0.1 m/s
}

// ECD mocap ground truth is noisy at the millisecond scale; the smoothed motion stays close to it but
// its path length over 5 ms samples shrinks towards the 100 ms path length (DESIGN.md §5).
TEST(SplineMotion, SmoothsMocapNoiseButFollowsTheTrajectory) {
  const std::string path = testing::dataPath("ecd/shapes_rotation/groundtruth.txt");
  const StampedTrajectory raw = readTumTrajectory(path);
  MotionFileOptions options;
  options.end_ns = raw.front().t_ns + 10'000'000'000;
  const auto motion = loadMotionFile(path, options);
  double sum_sq = 0, worst_angle = 0;
  int n = 0;
  double raw_length = 0, smooth_length = 0;
  for (std::size_t i = 0; i + 1 < raw.size() && raw[i + 1].t_ns <= motion->endNs(); ++i) {
    const StampedPose s = motion->pose(raw[i].t_ns);
    sum_sq += (s.p_w_c - raw[i].p_w_c).squaredNorm();
    worst_angle = std::max(worst_angle, angleBetween(s.q_w_c, raw[i].q_w_c));
    ++n;
    raw_length += (raw[i + 1].p_w_c - raw[i].p_w_c).norm();
    smooth_length += (motion->pose(raw[i + 1].t_ns).p_w_c - s.p_w_c).norm();
  }
  double coarse_length = 0;
  for (int64_t t = motion->beginNs(); t + 100'000'000 <= motion->endNs(); t += 100'000'000) {
    const auto a = std::lower_bound(raw.begin(), raw.end(), t,
                                    [](const StampedPose& p, int64_t v) { return p.t_ns < v; });
    const auto b = std::lower_bound(raw.begin(), raw.end(), t + 100'000'000,
                                    [](const StampedPose& p, int64_t v) { return p.t_ns < v; });
    coarse_length += (b->p_w_c - a->p_w_c).norm();
  }
  const double rms = std::sqrt(sum_sq / n);
  std::printf(
      "[ figure ] shapes_rotation 10 s: smoothed vs raw RMS %.2f mm, worst %.2f deg; path length raw(5 ms) "
      "%.3f m, smoothed(5 ms) %.3f m, raw(100 ms) %.3f m\n",
      rms * 1e3, worst_angle * 57.2958, raw_length, smooth_length, coarse_length);
  EXPECT_LT(rms, 0.003);
  EXPECT_LT(worst_angle, 0.03);
  EXPECT_LT(smooth_length, raw_length);
  EXPECT_LT(smooth_length, 1.15 * coarse_length);
}

TEST(SplineMotion, TimeWindowAndErrors) {
  const std::string path = testing::dataPath("ecd/shapes_rotation/groundtruth.txt");
  MotionFileOptions options;
  options.begin_ns = 5'000'000'000;
  options.end_ns = 6'000'000'000;
  const auto motion = loadMotionFile(path, options);
  EXPECT_EQ(motion->beginNs(), 5'000'000'000);
  EXPECT_EQ(motion->endNs(), 6'000'000'000);
  options.begin_ns = 100'000'000'000;  // after the file's end
  options.end_ns = 101'000'000'000;
  EXPECT_THROW(loadMotionFile(path, options), InputError);
  EXPECT_THROW(loadMotionFile(testing::dataPath("missing.txt")), InputError);
}

}  // namespace
}  // namespace asynevo::sim
