// The depth-reversed alternative of a two-view motion: narrow views of a lateral translation can be
// fitted with the translation reversed and the rotation turned further; the chirality-charging cost
// tells the two apart where the epipolar error alone cannot.
#include "asynevo/backend/depth_reversal.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>
#include <utility>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {
namespace {

constexpr double kFocal = 300.0;

struct Views {
  std::vector<lie::Vec3> a, b;
};

/// `n` points 2–6 m ahead inside a narrow view (±0.25 rad), seen from camera a and from camera b with
/// x_b = R x_a + t, with `noise_px` Gaussian noise on each image point.
Views narrowViews(const TwoViewMotion& m, double baseline, int n, double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-0.25, 0.25), depth(2.0, 6.0);
  std::normal_distribution<double> gaussian(0.0, noise_px / kFocal);
  const auto bearing = [&](const lie::Vec3& p) {
    return lie::Vec3(p.x() / p.z() + gaussian(rng), p.y() / p.z() + gaussian(rng), 1.0).normalized();
  };
  Views v;
  for (int i = 0; i < n; ++i) {
    const double z = depth(rng);
    const lie::Vec3 p_a(std::tan(angle(rng)) * z, std::tan(angle(rng)) * z, z);
    v.a.push_back(bearing(p_a));
    v.b.push_back(bearing(m.R_b_a * p_a + baseline * m.t_b_a));
  }
  return v;
}

double angleDeg(const lie::Vec3& u, const lie::Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI;
}

/// A lateral translation of 0.15 m with a small rotation about the vertical axis.
TwoViewMotion sideways() {
  return {lie::so3::exp(lie::Vec3(0.0, 0.02, 0.0)), lie::Vec3(0.98, 0.1, 0.17).normalized()};
}

TEST(DepthReversal, TheTrueMotionExplainsNoiseFreeViewsExactly) {
  const TwoViewMotion truth = sideways();
  const Views v = narrowViews(truth, 0.15, 30, 0.0, 1);
  for (const double r : chiralResiduals(truth, v.a, v.b, kFocal)) EXPECT_NEAR(r, 0.0, 1e-9);
}

TEST(DepthReversal, APointBehindACameraCostsItsAngleFromTheRotatedRay) {
  // The same motion with the translation reversed puts every point behind: both residuals are the
  // angle between R a and b (in pixels), whatever the epipolar geometry says (t and −t share it).
  const TwoViewMotion truth = sideways();
  const Views v = narrowViews(truth, 0.15, 20, 0.0, 2);
  const TwoViewMotion flipped{truth.R_b_a, -truth.t_b_a};
  const std::vector<double> r = chiralResiduals(flipped, v.a, v.b, kFocal);
  for (std::size_t i = 0; i < v.a.size(); ++i) {
    const double angle_px = angleDeg(truth.R_b_a * v.a[i], v.b[i]) * M_PI / 180.0 * kFocal;
    EXPECT_GT(angle_px, 1.0);
    EXPECT_NEAR(std::abs(r[2 * i]), angle_px, 1e-6 * angle_px);
    EXPECT_NEAR(std::abs(r[2 * i + 1]), angle_px, 1e-6 * angle_px);
  }
  EXPECT_GT(chiralCost(flipped, v.a, v.b, kFocal, 1.0), 10.0 * chiralCost(truth, v.a, v.b, kFocal, 1.0));
}

TEST(DepthReversal, FindsTheReversedAlternativeOfANarrowLateralMotionAndItFitsWorse) {
  const TwoViewMotion truth = sideways();
  const Views v = narrowViews(truth, 0.15, 40, 0.5, 3);
  const auto found = findDepthReversal(truth, v.a, v.b, kFocal, 1.0);
  EXPECT_LT(angleDeg(found.given.t_b_a, truth.t_b_a), 10.0);
  ASSERT_TRUE(found.reversed.has_value());
  EXPECT_GT(angleDeg(found.reversed->t_b_a, truth.t_b_a), 120.0);
  // The alternative turns further than the truth: the rotation makes up the reversed translation's flow.
  EXPECT_GT(lie::so3::log(found.reversed->R_b_a).norm(), lie::so3::log(truth.R_b_a).norm());
  EXPECT_GT(found.reversed_cost, found.given_cost);
}

TEST(DepthReversal, FromTheReversedMotionItFindsTheTrueOneAsTheBetterFit) {
  // A five-point pose that took the reversed minimum: its alternative is the true motion, and fits better.
  const TwoViewMotion truth = sideways();
  const Views v = narrowViews(truth, 0.15, 40, 0.5, 3);
  const auto from_truth = findDepthReversal(truth, v.a, v.b, kFocal, 1.0);
  ASSERT_TRUE(from_truth.reversed.has_value());
  const auto found = findDepthReversal(*from_truth.reversed, v.a, v.b, kFocal, 1.0);
  ASSERT_TRUE(found.reversed.has_value());
  EXPECT_LT(angleDeg(found.reversed->t_b_a, truth.t_b_a), 10.0);
  EXPECT_LT(found.reversed_cost, found.given_cost);
  EXPECT_NEAR(found.reversed_cost, from_truth.given_cost, 0.05 * from_truth.given_cost);
}

TEST(DepthReversal, AWideViewOfAForwardMotionHasNoCompetitiveAlternative) {
  // Moving forward, the flow expands from the epipole: no rotation makes up a reversed translation,
  // so whatever the search returns on the reversed side fits far worse.
  const TwoViewMotion forward{lie::so3::exp(lie::Vec3(0.0, 0.01, 0.0)), lie::Vec3(0.1, 0.0, 1.0).normalized()};
  const Views v = narrowViews(forward, 0.3, 40, 0.5, 4);
  const auto found = findDepthReversal(forward, v.a, v.b, kFocal, 1.0);
  EXPECT_LT(angleDeg(found.given.t_b_a, forward.t_b_a), 5.0);
  if (found.reversed) {
    EXPECT_GT(found.reversed_cost, 3.0 * found.given_cost);
  }
}

TEST(DepthReversal, AConstantTwistSeenOverPairsOfManySpansHasItsAlternativeToo) {
  // A multi-view start's pairs: each feature seen first at s and again 0.1–0.4 s later, the camera
  // moving sideways at constant twist. From the truth the reversed twist fits worse; from the reversed
  // twist the truth is found again and fits better.
  const ConstantTwist truth{lie::Vec3(0.0, 0.05, 0.01), lie::Vec3(1.0, 0.1, 0.15).normalized()};
  const double speed = 0.5;  // m/s
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-0.25, 0.25), depth(2.0, 6.0), span(0.1, 0.4);
  std::normal_distribution<double> noise(0.0, 0.5 / kFocal);
  std::vector<BearingPair> pairs;
  for (int i = 0; i < 50; ++i) {
    const double z = depth(rng), dt = span(rng);
    const lie::Vec3 p_s(std::tan(angle(rng)) * z, std::tan(angle(rng)) * z, z);
    TwoViewMotion m = motionOver(truth, dt);
    const lie::Vec3 p_e = m.R_b_a * p_s + speed * dt * m.t_b_a;
    const auto bearing = [&](const lie::Vec3& p) {
      return lie::Vec3(p.x() / p.z() + noise(rng), p.y() / p.z() + noise(rng), 1.0).normalized();
    };
    pairs.push_back({bearing(p_s), bearing(p_e), dt});
  }
  const DepthReversal<ConstantTwist> from_truth = findDepthReversal(truth, pairs, kFocal, 1.0);
  EXPECT_LT(angleDeg(from_truth.given.rho, truth.rho), 10.0);
  ASSERT_TRUE(from_truth.reversed.has_value());
  EXPECT_GT(angleDeg(from_truth.reversed->rho, truth.rho), 120.0);
  EXPECT_GT(from_truth.reversed_cost, from_truth.given_cost);
  const DepthReversal<ConstantTwist> from_reversed = findDepthReversal(*from_truth.reversed, pairs, kFocal, 1.0);
  ASSERT_TRUE(from_reversed.reversed.has_value());
  EXPECT_LT(angleDeg(from_reversed.reversed->rho, truth.rho), 10.0);
  EXPECT_LT(from_reversed.reversed_cost, from_reversed.given_cost);
}

TEST(DepthReversal, MotionOverATwistMovesPointsFromTheFirstCameraToTheSecond) {
  // exp(dt ξ) is camera e in the frame of camera s; motionOver gives x_e = R x_s + t, |t| = 1.
  const ConstantTwist w{lie::Vec3(0.1, -0.2, 0.05), lie::Vec3(0.3, 0.1, 0.9).normalized()};
  const double dt = 0.4;
  lie::Vec6 xi;
  xi << dt * w.rho, dt * w.phi;
  const lie::SE3 T_s_e = lie::se3::exp(xi);
  const lie::Vec3 p_s(0.4, -0.3, 3.0);
  const lie::Vec3 p_e = T_s_e.inverse() * p_s;
  const TwoViewMotion m = motionOver(w, dt);
  EXPECT_NEAR(m.t_b_a.norm(), 1.0, 1e-12);
  const double scale = T_s_e.translation().norm();
  EXPECT_LT((m.R_b_a * p_s + scale * m.t_b_a - p_e).norm(), 1e-12);
}

/// The decision of each rule on a comparison whose alternative costs `ratio` times the motion's.
std::string decided(const char* rule, double ratio, InitResult* r) {
  BackendConfig config;
  config.init_depth_reversal = rule;
  config.init_reversal_margin = 0.2;
  ReversalCheck check;
  check.features = 20;
  check.cost = 10.0;
  check.reversed_cost = 10.0 * ratio;
  check.found = true;
  return std::string(decideReversal(check, "167 ms", config, r));
}

TEST(DepthReversal, EachRuleDecidesByTheRatioOfTheTwoCostsAndTheMargin) {
  // best: the alternative only when cheaper by the margin; wait: also a tie within it; strict: a start
  // only when the alternative is dearer by 1 / (1 - margin) = 1.25.
  const std::vector<std::pair<double, std::array<const char*, 3>>> cases = {
      {0.7, {"reversed", "reversed", "tie"}}, {0.85, {"kept", "tie", "tie"}}, {1.1, {"kept", "tie", "tie"}},
      {1.22, {"kept", "kept", "tie"}},        {1.3, {"kept", "kept", "kept"}}};
  for (const auto& [ratio, expected] : cases) {
    int k = 0;
    for (const char* rule : {"best", "wait", "strict"}) {
      InitResult r;
      EXPECT_EQ(decided(rule, ratio, &r), expected[k]) << rule << " at " << ratio;
      ASSERT_EQ(r.reversal_checks.size(), 1u);
      EXPECT_STREQ(r.reversal_checks[0].decision, expected[k]);
      if (std::string(expected[k]) == "tie") {
        EXPECT_EQ(r.rejection, InitRejection::Reversal);
        EXPECT_NE(r.failure.find("167 ms: the depth-reversed motion fits 20 features"), std::string::npos) << r.failure;
      } else {
        EXPECT_EQ(r.rejection, InitRejection::None);
      }
      ++k;
    }
  }
  InitResult none;
  ReversalCheck no_alternative;
  BackendConfig config;
  config.init_depth_reversal = "strict";
  EXPECT_EQ(decideReversal(no_alternative, "x", config, &none), "kept");
}

}  // namespace
}  // namespace asynevo::backend
