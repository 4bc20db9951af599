#pragma once
// Marginalization by Schur complement on the Markov blanket (reference/backend.md §7.1):
// linearize every factor touching the variables to remove x_m (robust weights folded in), build
//   H = Σ JᵢᵀJᵢ,  b = Σ Jᵢᵀrᵢ,  H* = H_rr − H_rm H_mm⁺ H_mr,  b* = b_r − H_rm H_mm⁺ b_m
// (H_mm⁺ = H_mm⁻¹ by Cholesky where H_mm is positive definite, else the pseudo-inverse with a relative
// eigenvalue threshold), and turn (H*, b*) into a LinearPriorFactor
// r(x) = r* + J*(x ⊟ x̄) on the remaining blanket blocks x_r, linearized at their current values.

#include <map>
#include <memory>
#include <set>
#include <vector>

#include "asynevo/backend/factor_graph.hpp"
#include "asynevo/backend/factors/linear_prior_factor.hpp"

namespace asynevo::backend {

struct MarginalizationResult {
  std::shared_ptr<LinearPriorFactor> prior;  ///< null when no block remains in the blanket
  std::vector<double*> prior_blocks;         ///< the blocks of `prior`, in its order
  int marginalized_dims = 0;
  int kept_dims = 0;
  int rank_mm = 0;       ///< numerical rank of H_mm
  int prior_rank = 0;    ///< rank of the resulting prior
  int factors = 0;
  int invalid_factors = 0;  ///< factors that refused to evaluate (left out)
};

/// `kinds` gives the kind of every block appearing in `factors`; `marginalized` the blocks to remove.
MarginalizationResult marginalize(const std::vector<const FactorEntry*>& factors, const std::set<double*>& marginalized,
                                  const std::map<double*, BlockKind>& kinds, double relative_threshold = 1e-12);

}  // namespace asynevo::backend
