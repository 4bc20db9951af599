#include "asynevo/backend/pivoted_cholesky.hpp"

#include <algorithm>
#include <stdexcept>

// LAPACK (Fortran interface; reference LAPACK 3.2 and later, Debian's liblapack3).
extern "C" void dpstrf_(const char* uplo, const int* n, double* a, const int* lda, int* piv, int* rank,
                        const double* tol, double* work, int* info);

namespace asynevo::backend {

PivotedCholesky pivotedCholesky(const Eigen::MatrixXd& A, double relative_tolerance) {
  if (A.rows() != A.cols()) throw std::invalid_argument("pivotedCholesky: the matrix is not square");
  PivotedCholesky out;
  const int n = static_cast<int>(A.rows());
  out.U.resize(0, n);
  if (n == 0 || !A.allFinite()) {
    out.ok = n == 0;
    return out;
  }
  const double d_max = A.diagonal().maxCoeff();
  if (!(d_max > 0.0)) {
    out.ok = true;  // nothing positive: rank 0
    return out;
  }
  Eigen::MatrixXd a = A;
  std::vector<int> piv(static_cast<std::size_t>(n));
  std::vector<double> work(2 * static_cast<std::size_t>(n));
  int rank = 0;
  int info = 0;
  const double tol = relative_tolerance * d_max;
  const char uplo = 'U';
  dpstrf_(&uplo, &n, a.data(), &n, piv.data(), &rank, &tol, work.data(), &info);
  if (info < 0) return out;  // an argument LAPACK rejected
  // info 0: full rank; 1: stopped at the tolerance (rank < n). Rows beyond the rank are not factored.
  out.ok = true;
  out.rank = rank;
  out.U = a.topRows(rank).triangularView<Eigen::Upper>();
  out.piv.resize(piv.size());
  std::transform(piv.begin(), piv.end(), out.piv.begin(), [](int p) { return p - 1; });
  return out;
}

}  // namespace asynevo::backend
