#include "asynevo/backend/factor_graph.hpp"

#include <cmath>

namespace asynevo::backend {

LinearizedFactor linearize(const FactorEntry& factor, const std::vector<BlockKind>& kinds) {
  const ceres::CostFunction& cost = *factor.cost;
  const int m = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  const std::size_t n_blocks = sizes.size();
  LinearizedFactor out;
  out.r.resize(m);
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> ambient(n_blocks);
  std::vector<double*> jacobian_ptrs(n_blocks);
  for (std::size_t i = 0; i < n_blocks; ++i) {
    ambient[i].resize(m, sizes[i]);
    jacobian_ptrs[i] = ambient[i].data();
  }
  out.valid = cost.Evaluate(factor.blocks.data(), out.r.data(), jacobian_ptrs.data());
  if (!out.valid || !out.r.allFinite()) {
    out.valid = false;
    return out;
  }
  out.J.resize(n_blocks);
  for (std::size_t i = 0; i < n_blocks; ++i) out.J[i] = ambient[i].leftCols(tangentSize(kinds[i], sizes[i]));

  if (factor.loss) {
    const double s = out.r.squaredNorm();
    double rho[3];
    factor.loss->Evaluate(s, rho);
    const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
    double alpha = 0.0;
    if (s > 0.0 && rho[2] > 0.0) alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
    for (std::size_t i = 0; i < n_blocks; ++i) {
      if (alpha != 0.0) out.J[i] -= (alpha / s) * out.r * (out.r.transpose() * out.J[i]);
      out.J[i] *= sqrt_rho1;
    }
    out.r *= sqrt_rho1 / (1.0 - alpha);
  }
  return out;
}

}  // namespace asynevo::backend
