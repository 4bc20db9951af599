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


// rotation-dominated: the rotation preset's attitude, plus a translation of ~0.1 m/s peak (a path for
// Sim(3) alignment, far smaller than the rotation's image motion).
TEST(MotionPresets, RotationDominatedRotatesLikeRotationAndTranslatesALittle) {
  const auto dominated = makePresetMotion("rotation-dominated", 5.0);
  const auto rotation = makePresetMotion("rotation", 5.0);
  double path = 0, peak_speed = 0;
  for (int64_t t = 0; t < 5'000'000'000; t += 10'000'000) {
    EXPECT_LT(angleBetween(dominated->pose(t).q_w_c, rotation->pose(t).q_w_c), 1e-12);
    const double step = (dominated->pose(t + 10'000'000).p_w_c - dominated->pose(t).p_w_c).norm();
    path += step;
    peak_speed = std::max(peak_speed, step / 0.01);
  }
  EXPECT_GT(path, 0.1);
  EXPECT_GT(peak_speed, 0.05);
  EXPECT_LT(peak_speed, 0.15);
}
// --start S shows the preset's motion from S on, re-based to the preset's usual first pose: the relative
// motion between any two times equals the unshifted preset's between those times + S.
TEST(MotionPresets, StartOffsetShiftsThePhaseAndKeepsTheFirstPose) {
  for (const std::string& name : {std::string("6dof"), std::string("rotation"), std::string("slow-start")}) {
    const auto plain = makePresetMotion(name, 10.0);
    const auto shifted = makePresetMotion(name, 4.0, 3.0);
    EXPECT_EQ(shifted->beginNs(), 0);
    EXPECT_EQ(shifted->endNs(), 4'000'000'000);
    const StampedPose first = shifted->pose(0), first_plain = plain->pose(0);
    EXPECT_LT((first.p_w_c - first_plain.p_w_c).norm(), 1e-12) << name;
    EXPECT_LT(angleBetween(first.q_w_c, first_plain.q_w_c), 1e-12) << name;
    const StampedPose a_plain = plain->pose(3'000'000'000);
    for (int64_t t = 0; t <= 4'000'000'000; t += 250'000'000) {
      // T(0)⁻¹ T(t) of the shifted motion = T_f(S)⁻¹ T_f(t + S) of the plain one.
      const StampedPose b = shifted->pose(t), b_plain = plain->pose(t + 3'000'000'000);
      const Eigen::Quaterniond rel = first.q_w_c.conjugate() * b.q_w_c;
      const Eigen::Quaterniond rel_plain = a_plain.q_w_c.conjugate() * b_plain.q_w_c;
      const Eigen::Vector3d d = first.q_w_c.conjugate() * (b.p_w_c - first.p_w_c);
      const Eigen::Vector3d d_plain = a_plain.q_w_c.conjugate() * (b_plain.p_w_c - a_plain.p_w_c);
      ASSERT_LT(angleBetween(rel, rel_plain), 1e-12) << name << " t " << t;
      ASSERT_LT((d - d_plain).norm(), 1e-12) << name << " t " << t;
    }
    EXPECT_NE(shifted->describe().find("from 3 s"), std::string::npos) << shifted->describe();
  }
  // Start 0 is the plain preset, to the bit.
  const auto zero = makePresetMotion("6dof", 2.0, 0.0);
  const auto plain = makePresetMotion("6dof", 2.0);
  for (int64_t t = 0; t <= 2'000'000'000; t += 100'000'000) {
    EXPECT_TRUE(zero->pose(t).p_w_c == plain->pose(t).p_w_c);
    EXPECT_TRUE(zero->pose(t).q_w_c.coeffs() == plain->pose(t).q_w_c.coeffs());
  }
  EXPECT_THROW(makePresetMotion("6dof", 2.0, -1.0), std::invalid_argument);
}

// slow-start: nearly still (sub-millimetre, sub-milliradian) for 1.5 s, then a smooth ramp into 6dof.
TEST(MotionPresets, SlowStartIsStillFirstAndMovesLater) {
  const auto motion = makePresetMotion("slow-start", 5.0);
  const auto sixdof = makePresetMotion("6dof", 5.0);
  const StampedPose start = motion->pose(0);
  double still_offset = 0, still_angle = 0;
  for (int64_t t = 0; t <= 1'500'000'000; t += 10'000'000) {
    const StampedPose p = motion->pose(t);
    still_offset = std::max(still_offset, (p.p_w_c - start.p_w_c).norm());
    still_angle = std::max(still_angle, angleBetween(p.q_w_c, start.q_w_c));
  }
  EXPECT_LT(still_offset, 1e-3);
  EXPECT_LT(still_angle, 1e-3);
  // Speeds over 10 ms: tiny while still, then like the 6dof preset's (peak ~0.5 m/s) after the ramp.
  const auto speed = [](const Motion& m, int64_t t) {
    return (m.pose(t + 10'000'000).p_w_c - m.pose(t).p_w_c).norm() / 0.01;
  };
  double still_speed = 0, late_speed = 0, sixdof_speed = 0;
  for (int64_t t = 0; t < 1'500'000'000; t += 10'000'000) still_speed = std::max(still_speed, speed(*motion, t));
  for (int64_t t = 2'500'000'000; t < 4'990'000'000; t += 10'000'000) late_speed = std::max(late_speed, speed(*motion, t));
  for (int64_t t = 0; t < 2'490'000'000; t += 10'000'000) sixdof_speed = std::max(sixdof_speed, speed(*sixdof, t));
  EXPECT_LT(still_speed, 2e-3);
  EXPECT_GT(late_speed, 0.2);
  EXPECT_NEAR(late_speed, sixdof_speed, 0.05);  // after the ramp: 6dof from its phase 0, shifted by 2 s
  // After the ramp the motion is the 6dof preset at τ = t - 2 s (plus the 0.2 mm drift).
  for (int64_t t = 2'500'000'000; t <= 5'000'000'000; t += 250'000'000) {
    const StampedPose p = motion->pose(t), q = sixdof->pose(t - 2'000'000'000);
    ASSERT_LT((p.p_w_c - q.p_w_c).norm(), 1e-3);
    ASSERT_LT(angleBetween(p.q_w_c, q.q_w_c), 1e-3);
  }
  // The ramp is smooth: no velocity jump between 10 ms samples.
  double worst_jump = 0;
  for (int64_t t = 1'400'000'000; t < 2'700'000'000; t += 10'000'000)
    worst_jump = std::max(worst_jump, std::fabs(speed(*motion, t + 10'000'000) - speed(*motion, t)));
  EXPECT_LT(worst_jump, 0.02);
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
