#pragma once
// The factors of one window, with the parameter blocks each one touches, kept outside Ceres so the same
// factor objects serve the window solve (a ceres::Problem built from them) and the marginalization
// (linearized one by one). Ownership stays here; Ceres problems never take it.

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace asynevo::backend {

enum class BlockKind { kPose, kEuclidean };

struct FactorEntry {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;  ///< may be null
  std::vector<double*> blocks;
};

/// A factor linearized at the current block values: whitened, robust-corrected residual r and the
/// tangent Jacobian of each block (r.size() × tangent size).
struct LinearizedFactor {
  Eigen::VectorXd r;
  std::vector<Eigen::MatrixXd> J;
  bool valid = false;  ///< false when the cost function refused to evaluate (e.g. cheirality)
};

/// Tangent size of a block given its ambient size and kind (poses: 7 → 6).
inline int tangentSize(BlockKind kind, int ambient) { return kind == BlockKind::kPose ? 6 : ambient; }

/// Evaluates `factor` with Jacobians and applies the robust loss's Triggs correction (Triggs et al.,
/// "Bundle adjustment — a modern synthesis", 2000, §4.3; the same correction Ceres applies internally):
/// with s = |r|², ρ', ρ'': α = 1 − √(1 + 2sρ''/ρ') (0 if ρ'' ≤ 0 or s = 0),
/// r ← √ρ'/(1 − α) r,  J ← √ρ' (I − α r rᵀ/s) J. Pose blocks use the tangent-Jacobian convention
/// (first 6 of 7 ambient columns).
LinearizedFactor linearize(const FactorEntry& factor, const std::vector<BlockKind>& kinds);

}  // namespace asynevo::backend
