#pragma once
// Generic linear prior, the form a marginalization result takes in the problem (reference/backend.md
// §7.1; docs/math/gp_backend.md §6):
//   r(x) = r* + J* · (x ⊟ x̄),
// with x̄ the stored linearization point of every block and ⊟ the exact inverse of the solver's
// retraction: Log(T̄⁻¹T) for pose blocks (SE3Manifold), x − x̄ for Euclidean blocks. The Jacobian w.r.t.
// a pose block's tangent at the current x is J*_block · J_r⁻¹(x ⊟ x̄) (exact, not the usual J*_block).
//
// Also builds (J*, r*) from a Schur-complemented system (H*, b*) (H* = J*ᵀJ*, b* = J*ᵀr*, cost
// ½δᵀH*δ + b*ᵀδ + const) with a relative eigenvalue threshold.

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <vector>

namespace asynevo::backend {

/// One parameter block of a linear prior.
struct LinearPriorBlock {
  enum class Kind { kPose, kEuclidean };
  Kind kind = Kind::kEuclidean;
  /// Linearization point x̄ (7 values [t; q_xyzw] for a pose, else the Euclidean value).
  std::vector<double> linearization_point;

  int ambientSize() const { return static_cast<int>(linearization_point.size()); }
  int tangentSize() const { return kind == Kind::kPose ? 6 : ambientSize(); }
};

/// J* and r* of a linear prior, with the numerical rank kept.
struct LinearPriorSqrt {
  Eigen::MatrixXd J;  // rank × n
  Eigen::VectorXd r;  // rank
  int rank = 0;
  /// J*ᵀJ* and J*ᵀr* where they are the input H and b exactly (full rank); empty otherwise.
  Eigen::MatrixXd information;
  Eigen::VectorXd gradient;
};

/// Square-root form of the quadratic ½δᵀHδ + bᵀδ (H positive semi-definite). By Cholesky with complete
/// pivoting (pivotedCholesky), Pᵀ H P = UᵀU up to the first pivot ≤ rel_threshold × max diag(H): with U_k
/// the first k rows, J* = U_k Pᵀ and r* = U_kkᵀ⁻¹ (Pᵀb)_k. Should LAPACK fail, by the eigen-decomposition
/// H = V S Vᵀ: keep s > rel_threshold·s_max, J* = S^{1/2}Vᵀ, r* = S^{−1/2}Vᵀb (VINS-style eigen square
/// root). Either way ½|J*δ + r*|² equals the quadratic up to a constant on the kept directions.
LinearPriorSqrt linearPriorFromInformation(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                                           double rel_threshold = 1e-12);

class LinearPriorFactor final : public ceres::CostFunction {
 public:
  /// J has as many columns as the sum of the blocks' tangent sizes (in block order), r as many rows
  /// as J. The blocks' ambient sizes define the parameter block sizes.
  LinearPriorFactor(std::vector<LinearPriorBlock> blocks, Eigen::MatrixXd J, Eigen::VectorXd r);
  /// From a square-root form; its information and gradient are used as J*ᵀJ* and J*ᵀr* when it has them.
  LinearPriorFactor(std::vector<LinearPriorBlock> blocks, LinearPriorSqrt sqrt_form);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// The Gauss–Newton normal equations at `parameters` over the blocks' tangent layout: H = JᵀJ and
  /// g = Jᵀr with J and r as Evaluate returns them. With J = J*·D (D block-diagonal: J_r⁻¹(x ⊟ x̄) for a
  /// pose block, I otherwise), H = Dᵀ(J*ᵀJ*)D and g = Dᵀ(J*ᵀr* + J*ᵀJ*·(x ⊟ x̄)), from J*ᵀJ* and J*ᵀr*
  /// kept at construction: O(n²) per pose block instead of the O(m·n²) of forming JᵀJ.
  void normalEquations(double const* const* parameters, Eigen::MatrixXd& H, Eigen::VectorXd& g) const;

  const std::vector<LinearPriorBlock>& blocks() const { return blocks_; }
  const Eigen::MatrixXd& jacobian() const { return J_; }
  const Eigen::VectorXd& residual() const { return r_; }

 private:
  std::vector<LinearPriorBlock> blocks_;
  std::vector<int> tangent_offsets_;
  Eigen::MatrixXd J_;
  Eigen::VectorXd r_;
  Eigen::MatrixXd information_;  ///< J*ᵀJ*
  Eigen::VectorXd gradient_;     ///< J*ᵀr*
};

}  // namespace asynevo::backend
