#pragma once
// The depth-reversed alternative of a start's motion (docs/method/depth_reversal.md). In narrow views a
// lateral translation and a rotation move the image alike, and a motion can be fitted about as well
// with its translation reversed, its rotation turned further and the scene's inverse depths mirrored
// (1/Z' ≈ c − 1/Z: near points become far): the bas-relief / Necker ambiguity (Szeliski & Kang, "Shape
// ambiguities in structure from motion", IEEE TPAMI 19(5), 1997). The epipolar error alone cannot tell
// t from −t; the cost here also charges a point that would lie behind a camera, so the two minima have
// costs of their own and can be compared.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "asynevo/backend/init_result.hpp"
#include "asynevo/core/config/backend_config.hpp"
#include "asynevo/lie/so3.hpp"

namespace asynevo::backend {

/// x_b = R_b_a x_a + t_b_a (points from camera a to camera b), |t_b_a| = 1.
struct TwoViewMotion {
  lie::Mat3 R_b_a = lie::Mat3::Identity();
  lie::Vec3 t_b_a = lie::Vec3::UnitX();
};

/// Per correspondence two residuals in pixels (angle × focal): for a point in front of both cameras (or
/// too far for its depth sign to show) the angular distances of each view's bearing from the epipolar
/// plane of the other's; for a point the motion puts behind a camera, the best it can do without, a
/// point at infinity: the angle between R a and b, twice. Bearings are unit vectors.
std::vector<double> chiralResiduals(const TwoViewMotion& m, const std::vector<lie::Vec3>& a,
                                    const std::vector<lie::Vec3>& b, double focal);

/// Σ c² log(1 + (r/c)²) over chiralResiduals (Cauchy scale c in pixels).
double chiralCost(const TwoViewMotion& m, const std::vector<lie::Vec3>& a, const std::vector<lie::Vec3>& b,
                  double focal, double cauchy_px);

/// A feature seen along bearing `a` and, `dt` later, along bearing `b`.
struct BearingPair {
  lie::Vec3 a, b;
  double dt = 1.0;
};

/// A constant body twist: the camera at s + dt in the frame of the camera at s is exp(dt (ρ, φ)), with
/// rotation rate φ and translation direction ρ (unit; the scale of a monocular start is free).
struct ConstantTwist {
  lie::Vec3 phi = lie::Vec3::Zero();
  lie::Vec3 rho = lie::Vec3::UnitX();
};

/// The motion a twist makes over dt, as chiralResiduals takes it.
TwoViewMotion motionOver(const ConstantTwist& w, double dt);

/// Σ over pairs of the Cauchy cost of chiralResiduals under motionOver(w, dt).
double chiralCost(const ConstantTwist& w, const std::vector<BearingPair>& pairs, double focal, double cauchy_px);

template <typename Motion>
struct DepthReversal {
  Motion given;  ///< the given motion, refined on chiralCost
  double given_cost = 0;
  /// The lowest minimum found whose translation points against the given one's (none when every seed
  /// returned to the given side).
  std::optional<Motion> reversed;
  double reversed_cost = 0;
};

/// Refines `start` on chiralCost and searches its depth-reversed alternative from two seeds with −ρ:
/// the rotation rate that explains the image motion alone (where the sides of the points swap) and
/// that rate's reflection of the given one (the rotation turned as far again).
DepthReversal<ConstantTwist> findDepthReversal(const ConstantTwist& start, const std::vector<BearingPair>& pairs,
                                               double focal, double cauchy_px);

/// The same for two views (every pair one unit of time apart).
DepthReversal<TwoViewMotion> findDepthReversal(const TwoViewMotion& start, const std::vector<lie::Vec3>& a,
                                               const std::vector<lie::Vec3>& b, double focal, double cauchy_px);

/// Decides a comparison by the rule of init_depth_reversal ("best", "wait" or "strict", with
/// init_reversal_margin m), logs it in r->reversal_checks and returns the decision: "reversed" (best and
/// wait: build on the alternative, its cost is below (1 − m) × the motion's), "tie" (wait: the costs
/// within m of each other; strict: the alternative not dearer than the motion by 1 / (1 − m); r is then
/// rejected as a reversal, its failure naming the span, the features and both costs) or "kept".
std::string_view decideReversal(ReversalCheck check, const std::string& span, const BackendConfig& config,
                                InitResult* r);

}  // namespace asynevo::backend
