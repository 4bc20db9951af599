#pragma once
// A dense Levenberg–Marquardt for the few-parameter fits of the start (the multi-view twist, the start
// trajectory's rotations): forward-difference Jacobian, Cauchy weights by iterative reweighting, and
// parameters updated through a caller-given retraction. Private to src/backend.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>

namespace asynevo::backend::small_lm {

/// Σ c² log(1 + (r/c)²), the Cauchy cost of residuals r at scale c (c ≤ 0: plain least squares).
inline double cauchyCost(const Eigen::VectorXd& r, double c) {
  if (c <= 0) return r.squaredNorm();
  return (c * c * (r.array() / c).square().log1p()).sum();
}

/// The retraction of a rotation rate and a translation direction, x = (φ, ρ) with |ρ| = 1, over five
/// tangent directions: φ moves freely, ρ on the unit sphere along two directions orthogonal to it.
inline Eigen::VectorXd retractRateAndDirection(const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
  const Eigen::Vector3d rho = x.tail<3>().normalized();
  const Eigen::Vector3d helper = std::abs(rho.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = rho.cross(helper).normalized();
  const Eigen::Vector3d v = rho.cross(u);
  Eigen::VectorXd y(6);
  y << x.head<3>() + d.head<3>(), (rho + d(3) * u + d(4) * v).normalized();
  return y;
}

using Residuals = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
using Retraction = std::function<Eigen::VectorXd(const Eigen::VectorXd&, const Eigen::VectorXd&)>;

/// Minimizes the Cauchy cost (scale c) of residuals(x) over the `dim` tangent directions of `retract`.
/// Returns false when the cost is not finite.
inline bool minimize(Eigen::VectorXd* x, int dim, const Residuals& residuals, const Retraction& retract, double c,
                     int max_iterations) {
  auto cost = [c](const Eigen::VectorXd& r) { return cauchyCost(r, c); };
  Eigen::VectorXd r = residuals(*x);
  double f = cost(r);
  if (!std::isfinite(f)) return false;
  double lambda = 1e-3;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::MatrixXd J(r.size(), dim);
    for (int j = 0; j < dim; ++j) {
      const double h = 1e-7;
      J.col(j) = (residuals(retract(*x, Eigen::VectorXd::Unit(dim, j) * h)) - r) / h;
    }
    // Iteratively reweighted: the Cauchy weight of each residual at the current estimate.
    Eigen::ArrayXd w = Eigen::ArrayXd::Ones(r.size());
    if (c > 0) w = (1.0 + (r.array() / c).square()).inverse();
    const Eigen::MatrixXd H = J.transpose() * w.matrix().asDiagonal() * J;
    const Eigen::VectorXd g = J.transpose() * (w * r.array()).matrix();
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * (H.diagonal().array() + 1e-12).matrix();
      const Eigen::VectorXd delta = A.ldlt().solve(-g);
      const Eigen::VectorXd x_new = retract(*x, delta);
      const Eigen::VectorXd r_new = residuals(x_new);
      const double f_new = cost(r_new);
      if (std::isfinite(f_new) && f_new < f) {
        const bool converged = f - f_new < 1e-10 * f || delta.norm() < 1e-10;
        *x = x_new;
        r = r_new;
        f = f_new;
        lambda = std::max(lambda / 3.0, 1e-9);
        improved = true;
        if (converged) return true;
      } else {
        lambda *= 4.0;
      }
    }
    if (!improved) break;
  }
  return std::isfinite(f);
}

}  // namespace asynevo::backend::small_lm
