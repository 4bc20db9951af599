#pragma once
// Helpers for the gp tests: random knot pairs with a prescribed inter-knot motion ‖ξ‖ and central
// differences through the retraction (T·Exp(δ) for poses, +δ for velocities), as in
// reference/backend.md §5.

#include <functional>
#include <random>

#include "asynevo/gp/wnoa.hpp"

namespace asynevo::gp::testing {

inline Vec6 randomVec6(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec6 v;
  for (int i = 0; i < 6; ++i) v[i] = n(rng);
  return scale * v / v.norm();
}

/// Two knots Δt apart whose relative motion has norm ‖ξ‖ = xi_norm, with velocities close to
/// (but not exactly) the constant-velocity ones, so every Jacobian block is exercised.
struct KnotPair {
  SE3 T_k;
  Vec6 w_k;
  SE3 T_k1;
  Vec6 w_k1;
  double dt;
};

inline KnotPair randomKnotPair(std::mt19937& rng, double xi_norm, double dt = 0.1) {
  KnotPair p;
  p.dt = dt;
  p.T_k = lie::se3::exp(randomVec6(rng, 1.5));
  const Vec6 xi = randomVec6(rng, xi_norm);
  p.T_k1 = p.T_k * lie::se3::exp(xi);
  p.w_k = xi / dt + randomVec6(rng, 0.3 * xi_norm / dt);
  p.w_k1 = xi / dt + randomVec6(rng, 0.3 * xi_norm / dt);
  return p;
}

/// Central-difference Jacobian of f: R^6 (tangent of one input) → R^n, with f already composed with
/// the retraction of that input and the output's own difference.
template <int N>
Eigen::Matrix<double, N, 6> numericJacobian(const std::function<Eigen::Matrix<double, N, 1>(const Vec6&)>& f,
                                            double h = 1e-6) {
  Eigen::Matrix<double, N, 6> J;
  for (int i = 0; i < 6; ++i) {
    const Vec6 d = Vec6::Unit(i) * h;
    J.col(i) = (f(d) - f(-d)) / (2.0 * h);
  }
  return J;
}

inline double maxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

}  // namespace asynevo::gp::testing
