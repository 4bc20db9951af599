#include "asynevo/backend/pivoted_cholesky.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace asynevo::backend {
namespace {

Eigen::MatrixXd randomMatrix(int rows, int cols, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < m.size(); ++i) m(i) = n(rng);
  return m;
}

/// P U_kᵀ U_k Pᵀ from the factorization, in A's order.
Eigen::MatrixXd reconstruct(const PivotedCholesky& chol) {
  const int n = static_cast<int>(chol.U.cols());
  Eigen::MatrixXd UP(chol.rank, n);  // U_k Pᵀ
  for (int j = 0; j < n; ++j) UP.col(chol.piv[j]) = chol.U.col(j);
  return UP.transpose() * UP;
}

TEST(PivotedCholesky, FullRankMatrixIsFactoredWhole) {
  std::mt19937 rng(1);
  const Eigen::MatrixXd B = randomMatrix(15, 12, rng);
  const Eigen::MatrixXd A = B.transpose() * B;
  const PivotedCholesky chol = pivotedCholesky(A, 1e-12);
  ASSERT_TRUE(chol.ok);
  EXPECT_EQ(chol.rank, 12);
  EXPECT_LT((reconstruct(chol) - A).cwiseAbs().maxCoeff(), 1e-12 * A.cwiseAbs().maxCoeff());
  // U is upper triangular and the pivots do not increase (largest remaining diagonal first).
  EXPECT_LT(chol.U.triangularView<Eigen::StrictlyLower>().toDenseMatrix().cwiseAbs().maxCoeff(), 1e-300);
  for (int k = 1; k < chol.rank; ++k) EXPECT_LE(chol.U(k, k), chol.U(k - 1, k - 1) * (1 + 1e-12)) << k;
}

TEST(PivotedCholesky, RankOfABadlyScaledRankDeficientMatrixIsFound) {
  // Rank 9 of 12, with the columns scaled over six orders of magnitude: the eigenvalues of the kept
  // directions spread over 1e-6..1e6, the null directions are rounding noise.
  std::mt19937 rng(2);
  const Eigen::MatrixXd B = randomMatrix(9, 12, rng);
  Eigen::VectorXd scale(12);
  for (int i = 0; i < 12; ++i) scale(i) = std::pow(10.0, -3.0 + 6.0 * i / 11.0);
  const Eigen::MatrixXd Bs = B * scale.asDiagonal();
  const Eigen::MatrixXd A = Bs.transpose() * Bs;
  const PivotedCholesky chol = pivotedCholesky(A, 1e-12);
  ASSERT_TRUE(chol.ok);
  EXPECT_EQ(chol.rank, 9);
  EXPECT_EQ(chol.U.rows(), 9);
  EXPECT_LT((reconstruct(chol) - A).cwiseAbs().maxCoeff(), 1e-10 * A.cwiseAbs().maxCoeff());
}

TEST(PivotedCholesky, ZeroEmptyAndNonFiniteMatrices) {
  const PivotedCholesky zero = pivotedCholesky(Eigen::MatrixXd::Zero(4, 4), 1e-12);
  EXPECT_TRUE(zero.ok);
  EXPECT_EQ(zero.rank, 0);
  EXPECT_EQ(zero.U.rows(), 0);
  EXPECT_EQ(zero.U.cols(), 4);
  const PivotedCholesky empty = pivotedCholesky(Eigen::MatrixXd(0, 0), 1e-12);
  EXPECT_TRUE(empty.ok);
  EXPECT_EQ(empty.rank, 0);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(3, 3);
  nan(1, 2) = nan(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(pivotedCholesky(nan, 1e-12).ok);
  EXPECT_THROW(pivotedCholesky(Eigen::MatrixXd::Identity(3, 2), 1e-12), std::invalid_argument);
}

}  // namespace
}  // namespace asynevo::backend
