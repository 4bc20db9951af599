#pragma once
// Cholesky factorization with complete (diagonal) pivoting of a symmetric positive semi-definite matrix,
// through LAPACK's dpstrf: Pᵀ A P = Uᵀ U, stopped at the first pivot ≤ a tolerance, which gives the
// numerical rank. Choosing the largest remaining diagonal of the updated matrix at every step makes it
// rank-revealing in practice (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., §10.3;
// LAPACK Working Note 161). Eigen's LDLT pivots on the original diagonal and is not rank-revealing.

#include <Eigen/Core>
#include <vector>

namespace asynevo::backend {

struct PivotedCholesky {
  bool ok = false;      ///< false: LAPACK reported an error (a non-finite input, say)
  int rank = 0;         ///< number of pivots above the tolerance
  Eigen::MatrixXd U;    ///< rank × n: the first `rank` rows of U (upper trapezoidal, in pivoted column order)
  std::vector<int> piv; ///< column j of A P is column piv[j] of A (0-based)
};

/// Factors A (n × n, symmetric; its upper triangle is read) and stops at the first pivot ≤
/// relative_tolerance × the largest diagonal of A. An empty or non-positive A has rank 0.
PivotedCholesky pivotedCholesky(const Eigen::MatrixXd& A, double relative_tolerance);

}  // namespace asynevo::backend
