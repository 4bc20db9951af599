#include "asynevo/backend/factors/linear_prior_factor.hpp"

#include <Eigen/Eigenvalues>
#include <stdexcept>
#include <utility>

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/backend/pivoted_cholesky.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

namespace {

/// Square root from the eigen-decomposition H = V S Vᵀ (any symmetric H).
LinearPriorSqrt sqrtByEigenvalues(const Eigen::MatrixXd& H_sym, const Eigen::VectorXd& b, double rel_threshold) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H_sym);
  const Eigen::VectorXd& s = eig.eigenvalues();  // ascending
  const double s_max = s.size() > 0 ? s.maxCoeff() : 0.0;
  LinearPriorSqrt out;
  if (!(s_max > 0.0)) {
    out.J.resize(0, H_sym.cols());
    out.r.resize(0);
    return out;
  }
  const double cut = rel_threshold * s_max;
  int first = 0;
  while (first < s.size() && s[first] <= cut) ++first;
  out.rank = static_cast<int>(s.size()) - first;
  const Eigen::MatrixXd V = eig.eigenvectors().rightCols(out.rank);
  const Eigen::VectorXd sv = s.tail(out.rank);
  out.J = sv.cwiseSqrt().asDiagonal() * V.transpose();
  out.r = sv.cwiseSqrt().cwiseInverse().asDiagonal() * (V.transpose() * b);
  return out;
}

}  // namespace

LinearPriorSqrt linearPriorFromInformation(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
                                           double rel_threshold) {
  const Eigen::MatrixXd H_sym = 0.5 * (H + H.transpose());
  const int n = static_cast<int>(H_sym.rows());
  // Pivoted Cholesky Pᵀ H P = UᵀU (pivoted_cholesky.hpp): a window's prior is rank-deficient (no absolute
  // pose or scale), and this finds its rank at a fraction of the eigen-decomposition's cost. With U_k the
  // first k rows: J* = U_k Pᵀ, so J*ᵀJ* = P U_kᵀU_k Pᵀ ≈ H; r* from J*ᵀr* = b on the k pivot rows,
  // U_k,kᵀ r* = (Pᵀb)_k (lower triangular).
  const PivotedCholesky chol = pivotedCholesky(H_sym, rel_threshold);
  if (!chol.ok) return sqrtByEigenvalues(H_sym, b, rel_threshold);
  const int k = chol.rank;
  LinearPriorSqrt out;
  out.rank = k;
  out.J.resize(k, n);
  Eigen::VectorXd Ptb(k);
  for (int j = 0; j < n; ++j) out.J.col(chol.piv[j]) = chol.U.col(j);
  for (int j = 0; j < k; ++j) Ptb(j) = b(chol.piv[j]);
  out.r = chol.U.leftCols(k).transpose().triangularView<Eigen::Lower>().solve(Ptb);
  if (k == n) {  // exact: J*ᵀJ* = H and J*ᵀr* = b
    out.information = H_sym;
    out.gradient = b;
  }
  return out;
}

LinearPriorFactor::LinearPriorFactor(std::vector<LinearPriorBlock> blocks, Eigen::MatrixXd J,
                                     Eigen::VectorXd r)
    : LinearPriorFactor(std::move(blocks), LinearPriorSqrt{std::move(J), std::move(r), 0, {}, {}}) {}

LinearPriorFactor::LinearPriorFactor(std::vector<LinearPriorBlock> blocks, LinearPriorSqrt sqrt_form)
    : blocks_(std::move(blocks)), J_(std::move(sqrt_form.J)), r_(std::move(sqrt_form.r)) {
  int offset = 0;
  for (const LinearPriorBlock& block : blocks_) {
    if (block.kind == LinearPriorBlock::Kind::kPose && block.ambientSize() != kPoseSize) {
      throw std::invalid_argument("LinearPriorFactor: a pose block needs a 7-value linearization point");
    }
    tangent_offsets_.push_back(offset);
    offset += block.tangentSize();
    mutable_parameter_block_sizes()->push_back(block.ambientSize());
  }
  if (J_.cols() != offset || J_.rows() != r_.size()) {
    throw std::invalid_argument("LinearPriorFactor: J must be (r.size() × total tangent size)");
  }
  set_num_residuals(static_cast<int>(r_.size()));
  if (sqrt_form.information.size() > 0) {  // J*ᵀJ* and J*ᵀr* as the marginalization had them: no product
    if (sqrt_form.information.rows() != J_.cols() || sqrt_form.information.cols() != J_.cols() ||
        sqrt_form.gradient.size() != J_.cols())
      throw std::invalid_argument("LinearPriorFactor: information and gradient must match J's columns");
    information_ = std::move(sqrt_form.information);
    gradient_ = std::move(sqrt_form.gradient);
  } else {
    information_.noalias() = J_.transpose() * J_;
    gradient_.noalias() = J_.transpose() * r_;
  }
}

void LinearPriorFactor::normalEquations(double const* const* parameters, Eigen::MatrixXd& H,
                                        Eigen::VectorXd& g) const {
  const int n = static_cast<int>(J_.cols());
  Eigen::VectorXd dx(n);
  std::vector<lie::Mat6> D(blocks_.size());
  for (size_t i = 0; i < blocks_.size(); ++i) {
    const LinearPriorBlock& block = blocks_[i];
    const int offset = tangent_offsets_[i];
    if (block.kind == LinearPriorBlock::Kind::kPose) {
      const lie::Vec6 d =
          lie::se3::boxMinus(poseFromBlock(parameters[i]), poseFromBlock(block.linearization_point.data()));
      dx.segment<6>(offset) = d;
      D[i] = lie::se3::rightJacobianInverse(d);
    } else {
      const int size = block.tangentSize();
      dx.segment(offset, size) = Eigen::Map<const Eigen::VectorXd>(parameters[i], size) -
                                 Eigen::Map<const Eigen::VectorXd>(block.linearization_point.data(), size);
    }
  }
  H = information_;
  g = gradient_;
  g.noalias() += information_ * dx;
  for (size_t i = 0; i < blocks_.size(); ++i) {
    if (blocks_[i].kind != LinearPriorBlock::Kind::kPose) continue;
    const int offset = tangent_offsets_[i];
    const lie::Mat6 Dt = D[i].transpose();
    H.middleRows<6>(offset) = Dt * H.middleRows<6>(offset);
    g.segment<6>(offset) = Dt * g.segment<6>(offset);
  }
  for (size_t i = 0; i < blocks_.size(); ++i) {
    if (blocks_[i].kind != LinearPriorBlock::Kind::kPose) continue;
    const int offset = tangent_offsets_[i];
    H.middleCols<6>(offset) = H.middleCols<6>(offset) * D[i];
  }
}

bool LinearPriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const int m = static_cast<int>(r_.size());
  Eigen::Map<Eigen::VectorXd> res(residuals, m);
  res = r_;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  for (size_t i = 0; i < blocks_.size(); ++i) {
    const LinearPriorBlock& block = blocks_[i];
    const int offset = tangent_offsets_[i];
    const int n = block.tangentSize();
    double* jac = jacobians != nullptr ? jacobians[i] : nullptr;
    if (block.kind == LinearPriorBlock::Kind::kPose) {
      const lie::Vec6 dx =
          lie::se3::boxMinus(poseFromBlock(parameters[i]), poseFromBlock(block.linearization_point.data()));
      res.noalias() += J_.middleCols<6>(offset) * dx;
      if (jac != nullptr) {
        Eigen::Map<RowMajor> J(jac, m, kPoseSize);
        J.leftCols<6>() = J_.middleCols<6>(offset) * lie::se3::rightJacobianInverse(dx);
        J.col(6).setZero();
      }
    } else {
      const Eigen::Map<const Eigen::VectorXd> x(parameters[i], n);
      const Eigen::Map<const Eigen::VectorXd> x_bar(block.linearization_point.data(), n);
      res.noalias() += J_.middleCols(offset, n) * (x - x_bar);
      if (jac != nullptr) Eigen::Map<RowMajor>{jac, m, n} = J_.middleCols(offset, n);
    }
  }
  return true;
}

}  // namespace asynevo::backend
