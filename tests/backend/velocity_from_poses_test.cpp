// The linear velocity of each final knot from the final positions of its segment
// (backend/velocity_from_poses.hpp).
#include "asynevo/backend/velocity_from_poses.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {
namespace {

constexpr int64_t kDtNs = 50'000'000;  // 50 ms between knots

/// A knot whose GP velocity is `gp` (7 everywhere unless given): what the class must leave alone.
Knot knotAt(int i, const lie::SE3& T, const lie::Vec6& gp = lie::Vec6::Constant(7.0)) {
  Knot k;
  k.t_ns = 1'000'000'000 + i * kDtNs;
  k.set(T, gp);
  return k;
}

std::vector<Knot> runThrough(VelocityFromPoses& velocity, const std::vector<Knot>& knots) {
  std::vector<Knot> out;
  for (const Knot& k : knots) velocity.push(k, out);
  velocity.flush(out);
  return out;
}

lie::Vec3 linear(const Knot& k) { return k.twist().head<3>(); }
lie::Vec3 angular(const Knot& k) { return k.twist().tail<3>(); }

// A constant body twist with the translation along the rotation axis: T(t) = Exp(t ϖ) with v ∥ ω keeps
// the camera on a line through the origin, p(t) = t·v, and R(t)ᵀv = v, so every difference is exact.
TEST(VelocityFromPoses, RecoversAConstantVelocityAlongTheRotationAxisAtEveryKnot) {
  lie::Vec6 w;
  w << 0.06, 0.12, -0.24, 0.2, 0.4, -0.8;  // v = 0.3 ω
  std::vector<Knot> knots;
  for (int i = 0; i < 12; ++i) knots.push_back(knotAt(i, lie::se3::exp(w * (i * 0.05))));
  for (int span : {1, 2, 3}) {
    VelocityFromPoses velocity(span);
    const std::vector<Knot> out = runThrough(velocity, knots);
    ASSERT_EQ(out.size(), knots.size()) << span;
    for (std::size_t i = 0; i < out.size(); ++i) {
      EXPECT_EQ(out[i].t_ns, knots[i].t_ns);
      EXPECT_EQ(out[i].pose, knots[i].pose) << "the pose is passed on bit for bit";
      EXPECT_EQ(angular(out[i]), angular(knots[i])) << "the angular velocity stays the GP's";
      EXPECT_LT((linear(out[i]) - w.head<3>()).norm(), 1e-9)
          << "span " << span << ", knot " << i << ": " << linear(out[i]).transpose();
    }
  }
}

// A general motion: the central difference is second-order accurate, the one-sided ones at the segment's
// ends first-order.
TEST(VelocityFromPoses, ApproximatesAVaryingVelocityToTheOrderOfItsDifference) {
  auto truth = [](double t) {
    lie::Vec6 xi;
    xi << 0.3 * std::sin(2 * t), 0.2 * t, 0.1 * std::cos(3 * t), 0.2 * std::sin(t), 0.4 * t, 0.1 * t * t;
    return lie::se3::exp(xi);
  };
  auto bodyVelocity = [&](double t) {  // Rᵀṗ by a fine central difference
    const double h = 1e-6;
    return lie::Vec3(truth(t).rotation().transpose() *
                     (truth(t + h).translation() - truth(t - h).translation()) / (2 * h));
  };
  std::vector<Knot> knots;
  for (int i = 0; i < 20; ++i) knots.push_back(knotAt(i, truth(i * 0.05)));
  VelocityFromPoses velocity(1);
  const std::vector<Knot> out = runThrough(velocity, knots);
  ASSERT_EQ(out.size(), knots.size());
  double worst_inside = 0, worst_end = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double err = (linear(out[i]) - bodyVelocity(i * 0.05)).norm();
    const bool end = i == 0 || i + 1 == out.size();
    (end ? worst_end : worst_inside) = std::max(end ? worst_end : worst_inside, err);
  }
  EXPECT_LT(worst_inside, 5e-3);  // O(Δt²): about 2e-3 m/s here
  EXPECT_LT(worst_end, 5e-2);     // O(Δt)
  EXPECT_GT(worst_end, worst_inside);
}

TEST(VelocityFromPoses, KnotsLeaveSpanKnotsLateAndTheRestWhenTheSegmentEnds) {
  std::vector<Knot> knots;
  for (int i = 0; i < 6; ++i) knots.push_back(knotAt(i, lie::se3::exp(lie::Vec6::Constant(0.01 * i))));
  VelocityFromPoses velocity(2);
  std::vector<Knot> out;
  for (int i = 0; i < 6; ++i) {
    velocity.push(knots[static_cast<std::size_t>(i)], out);
    EXPECT_EQ(out.size(), static_cast<std::size_t>(std::max(0, i - 1))) << "after knot " << i;
  }
  velocity.flush(out);
  ASSERT_EQ(out.size(), 6u);
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].t_ns, knots[i].t_ns);
  std::vector<Knot> none;
  velocity.flush(none);
  EXPECT_TRUE(none.empty()) << "a second flush has nothing left";
}

// After a flush (the segment ended) the next knots are a new segment: no difference spans the two.
TEST(VelocityFromPoses, ADifferenceNeverSpansTwoSegments) {
  lie::Vec6 wa = lie::Vec6::Zero(), wb = lie::Vec6::Zero();
  wa(0) = 0.5;
  wb(1) = -2.0;
  VelocityFromPoses velocity(2);
  std::vector<Knot> a, b;
  for (int i = 0; i < 5; ++i) a.push_back(knotAt(i, lie::se3::exp(wa * (i * 0.05))));
  // the second segment starts somewhere else, with another map and scale
  for (int i = 10; i < 15; ++i) b.push_back(knotAt(i, lie::se3::exp(wb * (i * 0.05))));
  const std::vector<Knot> out_a = runThrough(velocity, a);
  const std::vector<Knot> out_b = runThrough(velocity, b);
  ASSERT_EQ(out_a.size(), 5u);
  ASSERT_EQ(out_b.size(), 5u);
  for (const Knot& k : out_a) EXPECT_LT((linear(k) - wa.head<3>()).norm(), 1e-9);
  for (const Knot& k : out_b) EXPECT_LT((linear(k) - wb.head<3>()).norm(), 1e-9);
}

TEST(VelocityFromPoses, SpanZeroAndOneKnotSegmentsKeepTheGpVelocity) {
  lie::Vec6 gp;
  gp << 1, 2, 3, 4, 5, 6;
  std::vector<Knot> knots;
  for (int i = 0; i < 4; ++i) knots.push_back(knotAt(i, lie::se3::exp(lie::Vec6::Constant(0.1 * i)), gp));
  VelocityFromPoses off(0);
  std::vector<Knot> out;
  for (const Knot& k : knots) {
    off.push(k, out);
    ASSERT_EQ(out.back().t_ns, k.t_ns) << "span 0 passes each knot on at once";
  }
  for (const Knot& k : out) EXPECT_EQ(k.twist(), gp);
  VelocityFromPoses one(2);
  const std::vector<Knot> single = runThrough(one, {knots[0]});
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].twist(), gp) << "no neighbour to differentiate with";
  EXPECT_THROW(VelocityFromPoses(-1), std::invalid_argument);
}

}  // namespace
}  // namespace asynevo::backend
