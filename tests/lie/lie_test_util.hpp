#pragma once
// Shared helpers for the lie tests: the angle sweep of reference/backend.md §5.1 and deterministic
// random directions.

#include <cmath>
#include <random>
#include <vector>

#include "asynevo/lie/se3.hpp"

namespace asynevo::lie::testing {

/// θ sweep across the small-angle threshold and up to just below π (issue 5).
inline std::vector<double> angleSweep() { return {1e-9, 1e-5, 3e-3, 2e-2, 0.5, 2.0, 3.0, M_PI - 1e-6}; }

inline Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

/// A twist with rotation angle θ and a translation part of norm about 1.
inline Vec6 randomTwist(std::mt19937& rng, double theta) {
  Vec6 xi;
  xi << randomUnit(rng) * 0.8, randomUnit(rng) * theta;
  return xi;
}

/// Σ_{n=0}^{N} M^n / (n + shift)! — power series used as an independent reference.
template <int D>
Eigen::Matrix<double, D, D> powerSeries(const Eigen::Matrix<double, D, D>& M, int shift, int terms = 60) {
  Eigen::Matrix<double, D, D> sum = Eigen::Matrix<double, D, D>::Zero();
  Eigen::Matrix<double, D, D> power = Eigen::Matrix<double, D, D>::Identity();
  double factorial = 1.0;
  for (int k = 1; k <= shift; ++k) factorial *= k;
  for (int n = 0; n < terms; ++n) {
    sum += power / factorial;
    power = power * M;
    factorial *= (n + 1 + shift);
  }
  return sum;
}

/// A finite-difference step that never pushes a rotation across θ = π (where Log wraps).
inline double safeStep(double theta) { return std::min(1e-6, (M_PI - theta) / 10.0); }

}  // namespace asynevo::lie::testing
