#include "asynevo/backend/depth_reversal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "asynevo/lie/se3.hpp"
#include "small_lm.hpp"
#include "view_geometry.hpp"

namespace asynevo::backend {

namespace {

/// Parameters x = (φ, ρ), retracted by small_lm::retractRateAndDirection.
Eigen::VectorXd pack(const ConstantTwist& w) {
  Eigen::VectorXd x(6);
  x << w.phi, w.rho.normalized();
  return x;
}

ConstantTwist unpack(const Eigen::VectorXd& x) { return {x.head<3>(), x.tail<3>().normalized()}; }


/// The two residuals of one correspondence (chiralResiduals).
void pairResiduals(const TwoViewMotion& m, const lie::Vec3& a, const lie::Vec3& b, double focal, double* r_a,
                   double* r_b) {
  const lie::Vec3& t = m.t_b_a;
  const lie::Vec3 u = m.R_b_a * a;
  const lie::Vec3 n_b = t.cross(u), n_a = t.cross(b);  // normals of the two epipolar planes
  const double d_b = n_b.norm() > 1e-12 ? n_b.normalized().dot(b) : 0.0;
  const double d_a = n_a.norm() > 1e-12 ? n_a.normalized().dot(u) : 0.0;
  // min_angle 0: every point has a depth sign; one far away that noise puts behind costs about its
  // epipolar error anyway (at infinity the two residuals meet).
  if (view_geometry::chirality(m.R_b_a, t, a, b, 0.0) == view_geometry::Chirality::Behind) {
    const double angle = view_geometry::angleBetween(u, b);
    *r_a = std::copysign(angle, d_a) * focal;
    *r_b = std::copysign(angle, d_b) * focal;
  } else {
    *r_a = std::asin(std::clamp(d_a, -1.0, 1.0)) * focal;
    *r_b = std::asin(std::clamp(d_b, -1.0, 1.0)) * focal;
  }
}

Eigen::VectorXd residualVector(const ConstantTwist& w, const std::vector<BearingPair>& pairs, double focal) {
  Eigen::VectorXd r(2 * pairs.size());
  TwoViewMotion m;
  double m_dt = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!(pairs[i].dt == m_dt)) {  // pairs of one span share their motion
      m = motionOver(w, pairs[i].dt);
      m_dt = pairs[i].dt;
    }
    pairResiduals(m, pairs[i].a, pairs[i].b, focal, &r(2 * i), &r(2 * i + 1));
  }
  return r;
}

struct Minimum {
  ConstantTwist twist;
  double cost = 0;
  bool ok = false;
};

Minimum refine(const ConstantTwist& seed, const std::vector<BearingPair>& pairs, double focal, double cauchy_px) {
  Eigen::VectorXd x = pack(seed);
  const auto residuals = [&](const Eigen::VectorXd& p) { return residualVector(unpack(p), pairs, focal); };
  Minimum m;
  m.ok = small_lm::minimize(&x, 5, residuals, small_lm::retractRateAndDirection, cauchy_px, 50);
  m.twist = unpack(x);
  m.cost = chiralCost(m.twist, pairs, focal, cauchy_px);
  m.ok = m.ok && std::isfinite(m.cost) && x.allFinite();
  return m;
}

/// The rotation rate that best explains the image motion alone: a ≈ exp(dt φ) b (least squares from
/// `seed`).
lie::Vec3 rotationOnlyRate(const lie::Vec3& seed, const std::vector<BearingPair>& pairs) {
  Eigen::VectorXd x = seed;
  const auto residuals = [&](const Eigen::VectorXd& phi) {
    Eigen::VectorXd r(3 * pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i)
      r.segment<3>(3 * i) = lie::so3::exp(pairs[i].dt * lie::Vec3(phi)) * pairs[i].b - pairs[i].a;
    return r;
  };
  small_lm::minimize(&x, 3, residuals, [](const Eigen::VectorXd& v, const Eigen::VectorXd& d) {
    return Eigen::VectorXd(v + d);
  }, 0.0, 20);
  return x;
}

}  // namespace

TwoViewMotion motionOver(const ConstantTwist& w, double dt) {
  lie::Vec6 xi;
  xi << dt * w.rho, dt * w.phi;
  const lie::SE3 T_s_e = lie::se3::exp(xi);  // camera e in the frame of camera s
  // x_e = R_s_eᵀ x_s − R_s_eᵀ t_s_e.
  const lie::Mat3 R = T_s_e.rotation().transpose();
  const lie::Vec3 t = -(R * T_s_e.translation());
  return {R, t.norm() > 0 ? lie::Vec3(t.normalized()) : lie::Vec3::UnitX()};
}

double chiralCost(const ConstantTwist& w, const std::vector<BearingPair>& pairs, double focal, double cauchy_px) {
  return small_lm::cauchyCost(residualVector(w, pairs, focal), cauchy_px);
}

std::vector<double> chiralResiduals(const TwoViewMotion& m, const std::vector<lie::Vec3>& a,
                                    const std::vector<lie::Vec3>& b, double focal) {
  std::vector<double> r(2 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i) pairResiduals(m, a[i], b[i], focal, &r[2 * i], &r[2 * i + 1]);
  return r;
}

double chiralCost(const TwoViewMotion& m, const std::vector<lie::Vec3>& a, const std::vector<lie::Vec3>& b,
                  double focal, double cauchy_px) {
  const std::vector<double> r = chiralResiduals(m, a, b, focal);
  return small_lm::cauchyCost(Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size())),
                              cauchy_px);
}

DepthReversal<ConstantTwist> findDepthReversal(const ConstantTwist& start, const std::vector<BearingPair>& pairs,
                                               double focal, double cauchy_px) {
  DepthReversal<ConstantTwist> result;
  const Minimum given = refine(start, pairs, focal, cauchy_px);
  result.given = given.ok ? given.twist : start;
  result.given_cost = given.ok ? given.cost : chiralCost(start, pairs, focal, cauchy_px);
  const lie::Vec3 rho0 = result.given.rho;
  const lie::Vec3 phi_rot = rotationOnlyRate(result.given.phi, pairs);
  for (const lie::Vec3& phi : {phi_rot, lie::Vec3(2.0 * phi_rot - result.given.phi)}) {
    const Minimum m = refine({phi, -rho0}, pairs, focal, cauchy_px);
    if (!m.ok || m.twist.rho.dot(rho0) >= 0) continue;  // back on the given side
    if (!result.reversed || m.cost < result.reversed_cost) {
      result.reversed = m.twist;
      result.reversed_cost = m.cost;
    }
  }
  return result;
}

DepthReversal<TwoViewMotion> findDepthReversal(const TwoViewMotion& start, const std::vector<lie::Vec3>& a,
                                               const std::vector<lie::Vec3>& b, double focal, double cauchy_px) {
  std::vector<BearingPair> pairs;
  for (std::size_t i = 0; i < a.size(); ++i) pairs.push_back({a[i], b[i], 1.0});
  // The twist over one unit of time that moves camera a to camera b: T_a_b = (R_b_a, t_b_a)⁻¹.
  const lie::Vec6 xi = lie::se3::log(lie::SE3(start.R_b_a, start.t_b_a).inverse());
  const DepthReversal<ConstantTwist> found =
      findDepthReversal(ConstantTwist{xi.tail<3>(), xi.head<3>().normalized()}, pairs, focal, cauchy_px);
  DepthReversal<TwoViewMotion> result;
  result.given = motionOver(found.given, 1.0);
  result.given_cost = found.given_cost;
  if (found.reversed) {
    result.reversed = motionOver(*found.reversed, 1.0);
    result.reversed_cost = found.reversed_cost;
  }
  return result;
}

std::string_view decideReversal(ReversalCheck check, const std::string& span, const BackendConfig& config,
                                InitResult* r) {
  const double margin = config.init_reversal_margin;
  const double ratio = check.reversed_cost / std::max(check.cost, 1e-12);
  const std::string& rule = config.init_depth_reversal;
  check.decision = "kept";
  if (check.found && rule == "strict") {
    if (ratio * (1.0 - margin) < 1.0) check.decision = "tie";  // not dearer by 1 / (1 − margin)
  } else if (check.found) {
    if (rule == "wait" && std::abs(ratio - 1.0) <= margin) {
      check.decision = "tie";
    } else if (ratio < 1.0 - margin) {
      check.decision = "reversed";
    }
  }
  r->reversal_checks.push_back(check);
  if (std::string_view(check.decision) == "tie") {
    r->rejection = InitRejection::Reversal;
    r->failure =
        rule == "strict"
            ? fmt::format("{}: the depth-reversed motion fits {} features at a cost of {:.2f} against {:.2f} (need it "
                          "{:.0f} % dearer)",
                          span, check.features, check.reversed_cost, check.cost, (1.0 / (1.0 - margin) - 1.0) * 100.0)
            : fmt::format("{}: the depth-reversed motion fits {} features within {:.0f} % (cost {:.2f} against "
                          "{:.2f}, need a margin of {:.0f} %)",
                          span, check.features, std::abs(ratio - 1.0) * 100.0, check.reversed_cost, check.cost,
                          margin * 100.0);
  }
  return check.decision;
}

}  // namespace asynevo::backend
