#include "asynevo/backend/multiview_initializer.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "asynevo/backend/depth_reversal.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/lie/se3.hpp"
#include "small_lm.hpp"
#include "view_geometry.hpp"

namespace asynevo::backend {

namespace {

using small_lm::cauchyCost;
using small_lm::minimize;
using view_geometry::Chirality;

/// Two samples of one feature: its bearing at the earlier time s and at the later time e.
struct Pair {
  lie::Vec3 f_s, f_e;
  double dt = 0;  ///< e − s, seconds
  int track = 0;  ///< index into the sampled tracks
};

struct Samples {
  std::vector<Pair> pairs;
  std::vector<int> longest;  ///< per sampled track: its pair spanning the longest time
  std::vector<double> motion_px;  ///< per sampled track: image motion over its longest pair
};

/// Every feature sampled at the grid times it is defined at; pairs of its first sample with each later.
Samples sample(const TrackMap& tracks, int64_t t_a, int64_t t_b, double focal) {
  Samples s;
  for (const auto& [id, track] : tracks) {
    std::optional<Eigen::Vector2d> first;
    double first_s = 0;
    int longest = -1;
    for (int k = 0; k <= kMultiViewSteps; ++k) {
      const int64_t t = t_a + (t_b - t_a) * k / kMultiViewSteps;
      const auto p = track.pointAt(t);
      if (!p) continue;
      const double t_s = durationSeconds(t_a, t);
      if (!first) {
        first = p;
        first_s = t_s;
        continue;
      }
      longest = static_cast<int>(s.pairs.size());
      s.pairs.push_back({view_geometry::ray(first->x(), first->y()), view_geometry::ray(p->x(), p->y()),
                         t_s - first_s, static_cast<int>(s.longest.size())});
    }
    if (longest < 0) continue;
    s.longest.push_back(longest);
    const Pair& l = s.pairs[longest];
    s.motion_px.push_back(view_geometry::angleBetween(l.f_s, l.f_e) * focal);
  }
  return s;
}

/// The relative pose T_s_e = exp(dt ξ) (camera e in the frame of camera s), translation up to scale.
void relativePose(const ConstantTwist& w, double dt, lie::Mat3* R_s_e, lie::Vec3* t_s_e) {
  *R_s_e = lie::so3::exp(dt * w.phi);
  *t_s_e = lie::so3::leftJacobian(dt * w.phi) * w.rho;
}

/// Angular distance (rad) of the bearing at s from the epipolar plane of the motion and the bearing at e.
double epipolarError(const ConstantTwist& w, const Pair& p) {
  lie::Mat3 R;
  lie::Vec3 t;
  relativePose(w, p.dt, &R, &t);
  const lie::Vec3 n = t.cross(R * p.f_e);
  const double norm = n.norm();
  return norm < 1e-12 ? 0.0 : p.f_s.dot(n) / norm;
}

/// Rotation-only residual: the bearing at e rotated into s against the bearing at s (3 per pair).
Eigen::VectorXd rotationResiduals(const lie::Vec3& phi, const std::vector<Pair>& pairs) {
  Eigen::VectorXd r(3 * pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    r.segment<3>(3 * i) = lie::so3::exp(pairs[i].dt * phi) * pairs[i].f_e - pairs[i].f_s;
  }
  return r;
}

/// The rotation rate that best explains the image motion with no translation (Gauss–Newton from 0).
lie::Vec3 rotationOnlyRate(const std::vector<Pair>& pairs) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  minimize(&x, 3, [&](const Eigen::VectorXd& v) { return rotationResiduals(v, pairs); },
           [](const Eigen::VectorXd& v, const Eigen::VectorXd& d) { return Eigen::VectorXd(v + d); }, 0.0, 20);
  return x;
}

/// Given φ the epipolar constraints are linear in ρ, ρ · J_l(dt φ)ᵀ (R f_e × f_s) = 0: ρ is the
/// eigenvector of the smallest eigenvalue of their scatter matrix.
lie::Vec3 translationGivenRotation(const lie::Vec3& phi, const std::vector<Pair>& pairs) {
  lie::Mat3 M = lie::Mat3::Zero();
  for (const Pair& p : pairs) {
    const lie::Mat3 R = lie::so3::exp(p.dt * phi);
    const lie::Vec3 b = lie::so3::leftJacobian(p.dt * phi).transpose() * (R * p.f_e).cross(p.f_s);
    M += b * b.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<lie::Mat3> eigen(M);
  return eigen.eigenvectors().col(0).normalized();
}

/// Parameters (φ, ρ), retracted by small_lm::retractRateAndDirection.
Eigen::VectorXd pack(const ConstantTwist& w) {
  Eigen::VectorXd x(6);
  x << w.phi, w.rho;
  return x;
}
ConstantTwist unpack(const Eigen::VectorXd& x) {
  return ConstantTwist{x.head<3>(), x.tail<3>().normalized()};
}

Eigen::VectorXd epipolarResiduals(const ConstantTwist& w, const std::vector<Pair>& pairs) {
  Eigen::VectorXd r(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) r(i) = epipolarError(w, pairs[i]);
  return r;
}

/// The twist refined from a rotation seed; `cost` is its robust cost.
ConstantTwist refine(const lie::Vec3& phi_seed, const std::vector<Pair>& pairs, double c, double* cost) {
  ConstantTwist w{phi_seed, translationGivenRotation(phi_seed, pairs)};
  Eigen::VectorXd x = pack(w);
  const auto residuals = [&](const Eigen::VectorXd& v) { return epipolarResiduals(unpack(v), pairs); };
  if (!minimize(&x, 5, residuals, small_lm::retractRateAndDirection, c, 50)) {
    *cost = std::numeric_limits<double>::infinity();
    return w;
  }
  const Eigen::VectorXd r = residuals(x);
  *cost = cauchyCost(r, c);
  return unpack(x);
}

/// Per sampled track: whether every one of its pairs lies within three RANSAC thresholds (3c) of its
/// epipolar plane under w (the constant twist is only a model of the motion over the window).
std::vector<bool> fittingFeatures(const ConstantTwist& w, const Samples& s, double c) {
  std::vector<bool> fits(s.longest.size(), true);
  for (const Pair& p : s.pairs) {
    if (std::abs(epipolarError(w, p)) > 3.0 * c) fits[p.track] = false;
  }
  return fits;
}

/// Root-sum-square of per-feature parallaxes: the baseline direction's precision grows with it (each
/// feature's constraint weighs with its parallax squared), so many short tracks can stand in for the
/// two-view start's init_min_inliers features of init_min_parallax_px each.
double rootSumSquare(const std::vector<double>& v) {
  double sum = 0;
  for (const double x : v) sum += x * x;
  return std::sqrt(sum);
}

double requiredRootSumSquarePx(const BackendConfig& config) {
  return config.init_min_parallax_px * std::sqrt(static_cast<double>(config.init_min_inliers));
}

}  // namespace

InitResult initializeMultiView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                               const BackendConfig& config) {
  InitResult r;
  r.method = "multi-view";
  const int64_t window_ns = std::llround(config.init_window_ms * 1e6);
  r.t_a_ns = std::max(earliest_ns, t_b_ns - window_ns);
  r.t_b_ns = t_b_ns;
  const std::string span = fmt::format("multi-view {:.0f} ms", durationSeconds(r.t_a_ns, t_b_ns) * 1e3);
  if (t_b_ns - r.t_a_ns < window_ns / kMultiViewSteps * 2) {
    r.rejection = InitRejection::Features;
    r.failure = span + ": window shorter than two sample intervals";
    return r;
  }
  const Samples s = sample(tracks, r.t_a_ns, t_b_ns, focal);
  r.features = static_cast<int>(s.longest.size());
  if (r.features < config.init_min_features) {
    r.rejection = InitRejection::Features;
    r.failure = fmt::format("{}: {} features seen at two times or more (need {})", span, r.features,
                            config.init_min_features);
    return r;
  }
  const double required = requiredRootSumSquarePx(config);
  if (rootSumSquare(s.motion_px) < required) {
    r.rejection = InitRejection::Motion;
    r.failure = fmt::format("{}: image motion of {} features {:.0f} px root-sum-square (need {:.0f})", span,
                            r.features, rootSumSquare(s.motion_px), required);
    return r;
  }
  // Two seeds for the rotation rate, the rotation-only fit and none; the better robust fit wins.
  const double c = config.init_ransac_px / focal;
  double cost_fit = 0, cost_zero = 0;
  const ConstantTwist from_fit = refine(rotationOnlyRate(s.pairs), s.pairs, c, &cost_fit);
  const ConstantTwist from_zero = refine(lie::Vec3::Zero(), s.pairs, c, &cost_zero);
  ConstantTwist w = cost_fit <= cost_zero ? from_fit : from_zero;
  if (!std::isfinite(std::min(cost_fit, cost_zero)) || !w.phi.allFinite() || !w.rho.allFinite()) {
    r.rejection = InitRejection::Model;
    r.failure = fmt::format("{}: no constant-twist fit from {} features", span, r.features);
    return r;
  }
  // Refit on the features that fit: the robust loss bounds the pull of the others but does not remove it.
  std::vector<bool> fits = fittingFeatures(w, s, c);
  std::vector<Pair> fitting;
  for (const Pair& p : s.pairs) {
    if (fits[p.track]) fitting.push_back(p);
  }
  if (fitting.size() >= 5 && fitting.size() < s.pairs.size()) {
    double cost = 0;
    const ConstantTwist refit = refine(w.phi, fitting, c, &cost);
    if (std::isfinite(cost) && refit.phi.allFinite() && refit.rho.allFinite()) w = refit;
    fits = fittingFeatures(w, s, c);
  }
  // The sign of ρ: the one that puts more of the fitting features in front of both cameras, judged on
  // each feature's longest pair; features with too little parallax for a depth sign do not vote.
  const double min_angle = 2.0 * c;
  auto sides = [&](const ConstantTwist& candidate, int* front, int* not_behind) {
    *front = *not_behind = 0;
    for (std::size_t k = 0; k < s.longest.size(); ++k) {
      if (!fits[k]) continue;
      const Pair& p = s.pairs[s.longest[k]];
      lie::Mat3 R_s_e;
      lie::Vec3 t_s_e;
      relativePose(candidate, p.dt, &R_s_e, &t_s_e);
      // x_e = R_s_eᵀ x_s − R_s_eᵀ t_s_e: points from camera s to camera e.
      const Chirality side = view_geometry::chirality(R_s_e.transpose(), -(R_s_e.transpose() * t_s_e) * p.dt,
                                                      p.f_s, p.f_e, min_angle);
      *front += side == Chirality::Front;
      *not_behind += side != Chirality::Behind;
    }
  };
  int front_plus = 0, kept_plus = 0, front_minus = 0, kept_minus = 0;
  sides(w, &front_plus, &kept_plus);
  sides(ConstantTwist{w.phi, -w.rho}, &front_minus, &kept_minus);
  if (front_minus > front_plus) w.rho = -w.rho;
  r.inliers = front_minus > front_plus ? kept_minus : kept_plus;
  if (r.inliers < config.init_min_inliers) {
    r.rejection = InitRejection::Inliers;
    r.failure = fmt::format("{}: {} of {} features fit one constant twist in front of the cameras (need {})", span,
                            r.inliers, r.features, config.init_min_inliers);
    return r;
  }
  // The depth-reversed alternative (init_depth_reversal), fitted to every feature's longest pair: a
  // clearly better fit is built on, and "wait" leaves a tie.
  if (config.init_depth_reversal != "off") {
    std::vector<BearingPair> longest;
    for (const int k : s.longest) longest.push_back({s.pairs[k].f_s, s.pairs[k].f_e, s.pairs[k].dt});
    const auto reversal = findDepthReversal(w, longest, focal, config.init_ransac_px);
    const double span_s = durationSeconds(r.t_a_ns, t_b_ns);
    const std::string_view decision = decideReversal(
        {r.t_a_ns, t_b_ns, r.method, r.features, reversal.given_cost, reversal.reversed_cost,
         reversal.reversed.has_value(), motionOver(w, span_s).t_b_a,
         reversal.reversed ? motionOver(*reversal.reversed, span_s).t_b_a : lie::Vec3::Zero()},
        span, config, &r);
    if (decision == "tie") return r;
    if (decision == "reversed") {
      w = *reversal.reversed;
      fits = fittingFeatures(w, s, c);
      int front = 0;
      sides(w, &front, &r.inliers);
      r.depth_reversed = true;
      if (r.inliers < config.init_min_inliers) {
        r.rejection = InitRejection::Inliers;
        r.failure = fmt::format("{}: {} of {} features fit the depth-reversed twist, which fits better (need {})", span,
                                r.inliers, r.features, config.init_min_inliers);
        return r;
      }
    }
  }
  // Parallax once the rotation is removed, each fitting feature's longest pair (r.parallax_px: their RMS).
  std::vector<double> parallax;
  for (std::size_t k = 0; k < s.longest.size(); ++k) {
    if (!fits[k]) continue;
    const Pair& p = s.pairs[s.longest[k]];
    parallax.push_back(view_geometry::angleBetween(lie::so3::exp(p.dt * w.phi) * p.f_e, p.f_s) * focal);
  }
  const double total = rootSumSquare(parallax);
  r.parallax_px = total / std::sqrt(static_cast<double>(parallax.size()));
  if (total < required) {
    r.rejection = InitRejection::Parallax;
    r.failure = fmt::format(
        "{}: parallax of {} features {:.0f} px root-sum-square once the rotation ({:.1f} deg/s) is removed (need {:.0f})",
        span, parallax.size(), total, w.phi.norm() * 180.0 / M_PI, required);
    return r;
  }
  const double span_s = durationSeconds(r.t_a_ns, t_b_ns);
  lie::Vec6 xi;
  xi << w.rho * span_s, w.phi * span_s;
  const lie::SE3 T = lie::se3::exp(xi);
  r.T_a_b = lie::SE3(T.rotation(), T.translation().normalized());
  r.ok = true;
  return r;
}

}  // namespace asynevo::backend
