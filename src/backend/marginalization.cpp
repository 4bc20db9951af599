#include "asynevo/backend/marginalization.hpp"

#include <Eigen/Dense>
#include <stdexcept>

namespace asynevo::backend {

namespace {

struct BlockSlot {
  double* block;
  BlockKind kind;
  int ambient;
  int tangent;
  int offset = 0;
};

/// Whether `llt` factored a positive-definite matrix whose pivots L_ii² all exceed relative_threshold ×
/// the largest one (a small eigenvalue shows as a small pivot in practice; the pivots bound the
/// eigenvalues only from above, so this is a screen for the Cholesky path, not a proof of conditioning).
bool positiveDefinite(const Eigen::LLT<Eigen::MatrixXd>& llt, double relative_threshold) {
  if (llt.info() != Eigen::Success || llt.rows() == 0) return false;
  const Eigen::VectorXd pivots = llt.matrixLLT().diagonal().cwiseAbs2();
  return pivots.allFinite() && pivots.minCoeff() > relative_threshold * pivots.maxCoeff();
}

/// H* −= H_rm H_mm⁺ H_mr, b* −= H_rm H_mm⁺ b_m with the pseudo-inverse of the eigenvalues above
/// relative_threshold × the largest; `rank` counts them.
void schurByEigenvalues(const Eigen::MatrixXd& H_mm, const Eigen::MatrixXd& H_rm, const Eigen::VectorXd& b_m,
                        double relative_threshold, Eigen::MatrixXd& H_star, Eigen::VectorXd& b_star, int& rank) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(H_mm);
  const Eigen::VectorXd& s = eigen.eigenvalues();
  const double cut = relative_threshold * std::max(s.maxCoeff(), 0.0);
  const auto nm = s.size();
  Eigen::VectorXd s_inv = Eigen::VectorXd::Zero(nm);
  for (Eigen::Index i = 0; i < nm; ++i) {
    if (s(i) > cut && s(i) > 0) {
      s_inv(i) = 1.0 / s(i);
      ++rank;
    }
  }
  const Eigen::MatrixXd H_mm_pinv = eigen.eigenvectors() * s_inv.asDiagonal() * eigen.eigenvectors().transpose();
  H_star -= H_rm * H_mm_pinv * H_rm.transpose();
  b_star -= H_rm * H_mm_pinv * b_m;
}

}  // namespace

MarginalizationResult marginalize(const std::vector<const FactorEntry*>& factors, const std::set<double*>& marginalized,
                                  const std::map<double*, BlockKind>& kinds, double relative_threshold) {
  MarginalizationResult result;
  // Blocks in first-seen order (deterministic for a deterministic factor list), marginalized ones first.
  std::vector<BlockSlot> m_blocks, r_blocks;
  std::map<double*, std::pair<bool, int>> index;  // block -> (is marginalized, position)
  for (const FactorEntry* f : factors) {
    const auto& sizes = f->cost->parameter_block_sizes();
    for (std::size_t i = 0; i < f->blocks.size(); ++i) {
      double* b = f->blocks[i];
      if (index.count(b)) continue;
      const auto kind_it = kinds.find(b);
      if (kind_it == kinds.end()) throw std::logic_error("marginalize: a factor block has no registered kind");
      BlockSlot slot{b, kind_it->second, sizes[i], tangentSize(kind_it->second, sizes[i])};
      const bool is_m = marginalized.count(b) > 0;
      auto& list = is_m ? m_blocks : r_blocks;
      index[b] = {is_m, static_cast<int>(list.size())};
      list.push_back(slot);
    }
  }
  int dims = 0;
  for (auto& s : m_blocks) (s.offset = dims, dims += s.tangent);
  result.marginalized_dims = dims;
  for (auto& s : r_blocks) (s.offset = dims, dims += s.tangent);
  result.kept_dims = dims - result.marginalized_dims;

  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dims, dims);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dims);
  for (const FactorEntry* f : factors) {
    std::vector<BlockKind> block_kinds;
    std::vector<int> offsets;
    for (double* blk : f->blocks) {
      const auto [is_m, pos] = index[blk];
      const BlockSlot& s = is_m ? m_blocks[pos] : r_blocks[pos];
      block_kinds.push_back(s.kind);
      offsets.push_back(s.offset);
    }
    ++result.factors;
    const auto* linear_prior = dynamic_cast<const LinearPriorFactor*>(f->cost.get());
    if (linear_prior && !f->loss) {
      // The previous prior: its normal equations directly (O(n²) per pose block, not O(m·n²)).
      Eigen::MatrixXd H_prior;
      Eigen::VectorXd b_prior;
      linear_prior->normalEquations(f->blocks.data(), H_prior, b_prior);
      std::vector<int> local(f->blocks.size());
      for (std::size_t i = 0, col = 0; i < f->blocks.size(); ++i) {
        local[i] = static_cast<int>(col);
        col += static_cast<std::size_t>(linear_prior->blocks()[i].tangentSize());
      }
      for (std::size_t i = 0; i < f->blocks.size(); ++i) {
        const int ni = linear_prior->blocks()[i].tangentSize();
        b.segment(offsets[i], ni) += b_prior.segment(local[i], ni);
        for (std::size_t j = 0; j < f->blocks.size(); ++j) {
          const int nj = linear_prior->blocks()[j].tangentSize();
          H.block(offsets[i], offsets[j], ni, nj) += H_prior.block(local[i], local[j], ni, nj);
        }
      }
      continue;
    }
    const LinearizedFactor lin = linearize(*f, block_kinds);
    if (!lin.valid) {
      ++result.invalid_factors;
      continue;
    }
    for (std::size_t i = 0; i < lin.J.size(); ++i) {
      const int ni = static_cast<int>(lin.J[i].cols());
      b.segment(offsets[i], ni) += lin.J[i].transpose() * lin.r;
      for (std::size_t j = 0; j < lin.J.size(); ++j) {
        H.block(offsets[i], offsets[j], ni, lin.J[j].cols()) += lin.J[i].transpose() * lin.J[j];
      }
    }
  }

  const int nm = result.marginalized_dims;
  const int nr = result.kept_dims;
  if (nr == 0) return result;
  Eigen::MatrixXd H_star = H.bottomRightCorner(nr, nr);
  Eigen::VectorXd b_star = b.tail(nr);
  if (nm > 0) {
    const Eigen::MatrixXd H_mm = 0.5 * (H.topLeftCorner(nm, nm) + H.topLeftCorner(nm, nm).transpose());
    const Eigen::MatrixXd H_rm = H.bottomLeftCorner(nr, nm);
    // Full rank (the usual case): H_mm⁻¹ through its Cholesky factor, a few times cheaper than the
    // eigen-decomposition below, which stays for a rank-deficient H_mm (see positiveDefinite).
    const Eigen::LLT<Eigen::MatrixXd> llt(H_mm);
    if (positiveDefinite(llt, relative_threshold)) {
      result.rank_mm = nm;
      const Eigen::MatrixXd X = llt.solve(H_rm.transpose());  // H_mm⁻¹ H_mr
      H_star.noalias() -= H_rm * X;
      b_star.noalias() -= X.transpose() * b.head(nm);
    } else {
      schurByEigenvalues(H_mm, H_rm, b.head(nm), relative_threshold, H_star, b_star, result.rank_mm);
    }
  }
  H_star = 0.5 * (H_star + H_star.transpose());
  LinearPriorSqrt sqrt_form = linearPriorFromInformation(H_star, b_star, relative_threshold);
  result.prior_rank = sqrt_form.rank;
  if (sqrt_form.rank == 0) return result;  // nothing informative is left about the blanket

  std::vector<LinearPriorBlock> prior_blocks;
  for (const BlockSlot& s : r_blocks) {
    LinearPriorBlock block;
    block.kind = s.kind == BlockKind::kPose ? LinearPriorBlock::Kind::kPose : LinearPriorBlock::Kind::kEuclidean;
    block.linearization_point.assign(s.block, s.block + s.ambient);
    prior_blocks.push_back(std::move(block));
    result.prior_blocks.push_back(s.block);
  }
  result.prior = std::make_shared<LinearPriorFactor>(std::move(prior_blocks), std::move(sqrt_form));
  return result;
}

}  // namespace asynevo::backend
