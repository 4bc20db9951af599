#include "asynevo/backend/window_solver.hpp"

#include "asynevo/backend/factors/linear_prior_factor.hpp"
#include "range_workers.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <unordered_map>

namespace asynevo::backend {

struct WindowSolverWorkspace::Buffers {
  std::vector<double> residuals, jacobians, saved, factor_cost;
  std::vector<int> block_variables, block_jacobian_offsets, block_slots;
  Eigen::MatrixXd H, S;
  Eigen::VectorXd g, rhs, delta_c;
};

namespace {

using Clock = std::chrono::steady_clock;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using CameraLandmarkBlock = Eigen::Matrix<double, 6, 3>;  ///< ∂²/∂camera∂landmark; rows beyond the tangent are 0

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr double kMinDiagonal = 1e-6;  // Ceres's min_lm_diagonal / max_lm_diagonal
constexpr double kMaxDiagonal = 1e32;
constexpr int kMaxCameraTangent = 6;
/// Fewer factors than this per thread are evaluated on fewer threads (a thread's start costs about as much).
constexpr int kMinFactorsPerThread = 64;

double clampDiagonal(double d) { return std::clamp(d, kMinDiagonal, kMaxDiagonal); }

struct Variable {
  double* block = nullptr;
  BlockKind kind = BlockKind::kEuclidean;
  int ambient = 0;
  int tangent = 0;
  bool constant = false;
  int landmark = -1;  ///< index into the eliminated landmarks
  int offset = -1;    ///< position in the reduced system (camera variables)
};

struct Factor {
  const FactorEntry* entry = nullptr;
  int residuals = 0;
  int residual_offset = 0;
  /// Its blocks' entries in ArrowProblem's per-block arrays (variable, Jacobian offset, landmark slot):
  /// [first, first + blocks).
  int first = 0;
  int blocks = 0;
  int landmark = -1;                 ///< the eliminated landmark it touches (at most one), or −1
  int landmark_block = -1;
  bool fixed_size = false;           ///< 2 residuals, four camera blocks of tangent 6 (the GP projection)
  /// A linear prior without loss on camera blocks only: its normal equations come from the factor itself.
  const LinearPriorFactor* linear_prior = nullptr;
};

struct Landmark {
  int variable = -1;
  std::vector<int> slot_variables;  ///< camera variables coupled to it, in first-seen order
  Eigen::Matrix3d V = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  std::vector<CameraLandmarkBlock> W;
  Eigen::Matrix3d V_inv_damped = Eigen::Matrix3d::Zero();  ///< of the latest step
};

class ArrowProblem {
 public:
  ArrowProblem(const std::vector<FactorEntry>& entries, const std::map<double*, BlockKind>& kinds,
               const std::set<const double*>& landmarks, const std::set<const double*>& constant,
               const ceres::Manifold& manifold, WindowSolverWorkspace::Buffers& buffers)
      : manifold_(manifold),
        residuals_(buffers.residuals),
        jacobians_(buffers.jacobians),
        saved_(buffers.saved),
        factor_cost_(buffers.factor_cost),
        block_variables_(buffers.block_variables),
        block_jacobian_offsets_(buffers.block_jacobian_offsets),
        block_slots_(buffers.block_slots),
        H_(buffers.H),
        S_(buffers.S),
        g_(buffers.g),
        rhs_(buffers.rhs),
        delta_c_(buffers.delta_c) {
    std::unordered_map<const double*, int> index;
    auto variableOf = [&](double* block, int ambient) {
      const auto found = index.find(block);
      if (found != index.end()) return found->second;
      const auto kind = kinds.find(block);
      if (kind == kinds.end()) throw std::logic_error("solveWindow: a factor block has no registered kind");
      Variable v;
      v.block = block;
      v.kind = kind->second;
      v.ambient = ambient;
      v.tangent = tangentSize(v.kind, ambient);
      v.constant = constant.count(block) > 0;
      variables_.push_back(v);
      index.emplace(block, static_cast<int>(variables_.size()) - 1);
      return static_cast<int>(variables_.size()) - 1;
    };
    // A landmark is eliminated unless a factor touches it together with another landmark (the
    // marginalization prior over active landmarks): those stay in the dense system.
    std::set<int> coupled;
    factors_.reserve(entries.size());
    block_variables_.clear();
    block_jacobian_offsets_.clear();
    int residual_offset = 0;
    int jacobian_size = 0;
    std::vector<int> landmark_vars;
    for (const FactorEntry& e : entries) {
      Factor f;
      f.entry = &e;
      f.residuals = e.cost->num_residuals();
      f.residual_offset = residual_offset;
      residual_offset += f.residuals;
      f.first = static_cast<int>(block_variables_.size());
      f.blocks = static_cast<int>(e.blocks.size());
      const auto& sizes = e.cost->parameter_block_sizes();
      landmark_vars.clear();
      for (std::size_t b = 0; b < e.blocks.size(); ++b) {
        const int v = variableOf(e.blocks[b], sizes[b]);
        block_variables_.push_back(v);
        if (variables_[v].constant) {
          block_jacobian_offsets_.push_back(-1);
        } else {
          block_jacobian_offsets_.push_back(jacobian_size);
          jacobian_size += f.residuals * sizes[b];
        }
        if (!variables_[v].constant && landmarks.count(e.blocks[b])) landmark_vars.push_back(v);
      }
      if (landmark_vars.size() > 1) coupled.insert(landmark_vars.begin(), landmark_vars.end());
      factors_.push_back(f);
    }
    residuals_.resize(residual_offset);
    jacobians_.resize(jacobian_size);

    int offset = 0;
    for (int v = 0; v < static_cast<int>(variables_.size()); ++v) {
      Variable& var = variables_[v];
      if (var.constant) continue;
      if (landmarks.count(var.block) && !coupled.count(v) && var.tangent == 3) {
        var.landmark = static_cast<int>(landmarks_.size());
        landmarks_.emplace_back();
        landmarks_.back().variable = v;
      } else {
        if (var.tangent > kMaxCameraTangent) throw std::logic_error("solveWindow: a knot block wider than 6");
        var.offset = offset;
        offset += var.tangent;
      }
    }
    reduced_dims_ = offset;

    block_slots_.assign(block_variables_.size(), -1);
    for (Factor& f : factors_) {
      int camera_blocks = 0;
      bool all_six = true;
      for (int b = 0; b < f.blocks; ++b) {
        const Variable& var = variables_[blockVariable(f, b)];
        if (var.constant) continue;
        if (var.landmark >= 0) {
          f.landmark = var.landmark;
          f.landmark_block = static_cast<int>(b);
        } else {
          ++camera_blocks;
          all_six = all_six && var.tangent == 6;
        }
      }
      f.fixed_size = f.residuals == 2 && camera_blocks == 4 && all_six && f.blocks == 5 &&
                     f.landmark_block == 4;
      if (f.landmark < 0 && !f.entry->loss) f.linear_prior = dynamic_cast<const LinearPriorFactor*>(f.entry->cost.get());
      if (f.landmark < 0) continue;
      Landmark& lm = landmarks_[f.landmark];
      for (int b = 0; b < f.blocks; ++b) {
        const int v = blockVariable(f, b);
        const Variable& var = variables_[v];
        if (var.constant || var.landmark >= 0) continue;
        const auto found = std::find(lm.slot_variables.begin(), lm.slot_variables.end(), v);
        block_slots_[f.first + b] = static_cast<int>(found - lm.slot_variables.begin());
        if (found == lm.slot_variables.end()) lm.slot_variables.push_back(v);
      }
    }
    for (Landmark& lm : landmarks_) lm.W.resize(lm.slot_variables.size());

    // The order of evaluation: grouped by the factor's first block (a projection's knot interval starts
    // there), stable within a group. Any order gives the same result; this one lets splitEvaluation()
    // divide the factors between threads at group boundaries.
    eval_order_.resize(factors_.size());
    for (std::size_t i = 0; i < factors_.size(); ++i) eval_order_[i] = static_cast<int>(i);
    std::stable_sort(eval_order_.begin(), eval_order_.end(),
                     [&](int a, int b) { return groupOf(a) < groupOf(b); });
    splitEvaluation(1);
  }

  int reducedDims() const { return reduced_dims_; }
  int eliminatedLandmarks() const { return static_cast<int>(landmarks_.size()); }

  /// Σ ½ρ(|r|²) at the current values; with Jacobians, the robust-corrected residuals and Jacobians are
  /// kept for buildNormalEquations(). False when a factor refuses to evaluate or returns a non-finite value.
  /// The factors are evaluated in the ranges of splitEvaluation(), one per thread (the caller's and the
  /// workers'): every factor writes its own residuals, Jacobians and cost term, and the cost terms are
  /// summed in factor order afterwards, so the result is the same bit for bit on any number of threads.
  /// With `corrected_residuals` (and no Jacobians) the residuals are robust-corrected as with Jacobians,
  /// for buildGradient().
  bool evaluate(bool with_jacobians, double& cost, RangeWorkers& workers, bool corrected_residuals = false) {
    factor_cost_.resize(factors_.size());
    const int ranges = static_cast<int>(bounds_.size()) - 1;
    std::vector<char> range_ok(static_cast<std::size_t>(ranges), 1);
    workers.run(ranges, [&](int k) {
      range_ok[k] = evaluateRange(bounds_[k], bounds_[k + 1], with_jacobians, corrected_residuals);
    });
    if (!std::all_of(range_ok.begin(), range_ok.end(), [](char c) { return c != 0; })) return false;
    cost = 0.0;
    for (const double c : factor_cost_) cost += c;
    return true;
  }

  /// Splits eval_order_ into `ranges` ranges of about equal size that end where a group's factors end:
  /// the projections of one knot interval share its segment cache, which then stays with one thread.
  void splitEvaluation(int ranges) {
    const int n = static_cast<int>(factors_.size());
    bounds_.assign(1, 0);
    for (int k = 1; k < ranges; ++k) {
      int b = std::max(bounds_.back(), static_cast<int>(static_cast<int64_t>(n) * k / ranges));
      while (b > 0 && b < n && groupOf(eval_order_[b]) == groupOf(eval_order_[b - 1])) ++b;
      bounds_.push_back(b);
    }
    bounds_.push_back(n);
  }

  /// The threads evaluate() uses for `threads` requested: at most one per kMinFactorsPerThread factors.
  int evaluationThreads(int threads) const {
    return std::clamp(static_cast<int>(factors_.size()) / kMinFactorsPerThread, 1, std::max(threads, 1));
  }

  /// The group of factor i: its first block's variable.
  int groupOf(int i) const {
    const Factor& f = factors_[static_cast<std::size_t>(i)];
    return f.blocks == 0 ? -1 : blockVariable(f, 0);
  }

  /// Block b of factor f: its variable, its offset into the Jacobian buffer (−1: constant), and its
  /// slot among its landmark's camera blocks (−1: none).
  int blockVariable(const Factor& f, int b) const { return block_variables_[static_cast<std::size_t>(f.first + b)]; }
  int blockJacobian(const Factor& f, int b) const {
    return block_jacobian_offsets_[static_cast<std::size_t>(f.first + b)];
  }
  int blockSlot(const Factor& f, int b) const { return block_slots_[static_cast<std::size_t>(f.first + b)]; }

  /// evaluate() of the factors eval_order_[begin, end).
  bool evaluateRange(int begin, int end, bool with_jacobians, bool corrected_residuals) {
    std::vector<double*> jacobian_ptrs;
    for (int o = begin; o < end; ++o) {
      const int i = eval_order_[static_cast<std::size_t>(o)];
      const Factor& f = factors_[static_cast<std::size_t>(i)];
      const std::size_t n_blocks = static_cast<std::size_t>(f.blocks);
      jacobian_ptrs.assign(n_blocks, nullptr);
      const bool jacobians = with_jacobians && !f.linear_prior;
      if (jacobians) {
        for (int b = 0; b < f.blocks; ++b)
          if (blockJacobian(f, b) >= 0) jacobian_ptrs[b] = jacobians_.data() + blockJacobian(f, b);
      }
      double* r = residuals_.data() + f.residual_offset;
      if (!f.entry->cost->Evaluate(f.entry->blocks.data(), r, jacobians ? jacobian_ptrs.data() : nullptr))
        return false;
      Eigen::Map<Eigen::VectorXd> res(r, f.residuals);
      if (!res.allFinite()) return false;
      const double s = res.squaredNorm();
      double& cost = factor_cost_[static_cast<std::size_t>(i)];
      if (!f.entry->loss) {
        cost = 0.5 * s;
        continue;
      }
      double rho[3];
      f.entry->loss->Evaluate(s, rho);
      cost = 0.5 * rho[0];
      if (!with_jacobians && !corrected_residuals) continue;
      // Triggs correction, as linearize() in factor_graph.cpp.
      const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
      double alpha = 0.0;
      if (s > 0.0 && rho[2] > 0.0) alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
      const auto& sizes = f.entry->cost->parameter_block_sizes();
      for (std::size_t b = 0; b < n_blocks; ++b) {
        if (!jacobian_ptrs[b]) continue;
        Eigen::Map<RowMatrix> J(jacobian_ptrs[b], f.residuals, sizes[b]);
        if (alpha != 0.0) J -= (alpha / s) * res * (res.transpose() * J);
        J *= sqrt_rho1;
      }
      res *= sqrt_rho1 / (1.0 - alpha);
    }
    return true;
  }

  /// g and the landmarks' gradients from the residuals of the latest evaluate() (robust-corrected) and
  /// the Jacobians of the latest evaluate(true): a gradient at new values through the Jacobians of an
  /// earlier linearization (WindowSolverOptions::relinearize_every); H and the landmark blocks are kept.
  void buildGradient() {
    g_.setZero(reduced_dims_);
    for (Landmark& lm : landmarks_) lm.g.setZero();
    for (const Factor& f : factors_) {
      const auto& sizes = f.entry->cost->parameter_block_sizes();
      const Eigen::Map<const Eigen::VectorXd> r(residuals_.data() + f.residual_offset, f.residuals);
      if (f.linear_prior) {  // exact: a linear prior's gradient at the current values
        accumulateLinearPrior(f, false);
        continue;
      }
      for (int b = 0; b < f.blocks; ++b) {
        if (blockJacobian(f, b) < 0) continue;
        const Variable& var = variables_[blockVariable(f, b)];
        const auto J = Eigen::Map<const RowMatrix>(jacobians_.data() + blockJacobian(f, b), f.residuals, sizes[b])
                           .leftCols(var.tangent);
        if (var.landmark >= 0) {
          landmarks_[var.landmark].g.noalias() += J.transpose() * r;
        } else {
          g_.segment(var.offset, var.tangent).noalias() += J.transpose() * r;
        }
      }
    }
  }

  /// H (reduced part), g and the landmark blocks from the latest evaluate(true).
  void buildNormalEquations() {
    H_.setZero(reduced_dims_, reduced_dims_);
    g_.setZero(reduced_dims_);
    for (Landmark& lm : landmarks_) {
      lm.V.setZero();
      lm.g.setZero();
      for (CameraLandmarkBlock& w : lm.W) w.setZero();
    }
    for (const Factor& f : factors_) {
      const auto& sizes = f.entry->cost->parameter_block_sizes();
      const Eigen::Map<const Eigen::VectorXd> r(residuals_.data() + f.residual_offset, f.residuals);
      auto jacobian = [&](int b) {
        const Variable& var = variables_[blockVariable(f, b)];
        return Eigen::Map<const RowMatrix>(jacobians_.data() + blockJacobian(f, b), f.residuals, sizes[b])
            .leftCols(var.tangent);
      };
      if (f.fixed_size) {
        accumulateProjection(f);
        continue;
      }
      if (f.linear_prior) {
        accumulateLinearPrior(f);
        continue;
      }
      // The camera blocks side by side (m × K): one product for all their pairs.
      int width = 0;
      for (int b = 0; b < f.blocks; ++b) {
        const Variable& var = variables_[blockVariable(f, b)];
        if (!var.constant && var.landmark < 0) width += var.tangent;
      }
      if (width > 0) {
        camera_jacobian_.resize(f.residuals, width);
        int col = 0;
        for (int i = 0; i < f.blocks; ++i) {
          const Variable& vi = variables_[blockVariable(f, i)];
          if (vi.constant || vi.landmark >= 0) continue;
          camera_jacobian_.middleCols(col, vi.tangent) = jacobian(i);
          col += vi.tangent;
        }
        camera_information_.noalias() = camera_jacobian_.transpose() * camera_jacobian_;
        camera_gradient_.noalias() = camera_jacobian_.transpose() * r;
        int ci = 0;
        for (int i = 0; i < f.blocks; ++i) {
          const Variable& vi = variables_[blockVariable(f, i)];
          if (vi.constant || vi.landmark >= 0) continue;
          g_.segment(vi.offset, vi.tangent) += camera_gradient_.segment(ci, vi.tangent);
          int cj = 0;
          for (int j = 0; j < f.blocks; ++j) {
            const Variable& vj = variables_[blockVariable(f, j)];
            if (vj.constant || vj.landmark >= 0) continue;
            if (vj.offset <= vi.offset)
              H_.block(vi.offset, vj.offset, vi.tangent, vj.tangent) +=
                  camera_information_.block(ci, cj, vi.tangent, vj.tangent);
            cj += vj.tangent;
          }
          ci += vi.tangent;
        }
      }
      if (f.landmark < 0) continue;
      Landmark& lm = landmarks_[f.landmark];
      const auto Jl = jacobian(f.landmark_block);
      lm.V.noalias() += Jl.transpose() * Jl;
      lm.g.noalias() += Jl.transpose() * r;
      for (int i = 0; i < f.blocks; ++i) {
        if (blockSlot(f, i) < 0) continue;
        const Variable& vi = variables_[blockVariable(f, i)];
        lm.W[blockSlot(f, i)].topRows(vi.tangent).noalias() += jacobian(i).transpose() * Jl;
      }
    }
    // The projections fill the lower triangle only (the Cholesky factorization reads no more).
    H_.triangularView<Eigen::StrictlyUpper>() = H_.transpose();
  }

  /// The step δ of (H + μD)δ = −g, D = clamped diag(H), by eliminating the landmarks; false when the
  /// reduced system is not positive definite. Also returns the model cost decrease ½μδᵀDδ − ½gᵀδ.
  bool solveStep(double mu, double& model_decrease) {
    S_ = H_;
    rhs_ = g_;
    double d_delta = 0.0;  // δᵀDδ, accumulated below
    for (int i = 0; i < reduced_dims_; ++i) S_(i, i) += mu * clampDiagonal(H_(i, i));
    for (Landmark& lm : landmarks_) {
      Eigen::Matrix3d V = lm.V;
      for (int k = 0; k < 3; ++k) V(k, k) += mu * clampDiagonal(lm.V(k, k));
      const Eigen::LLT<Eigen::Matrix3d> llt(V);
      if (llt.info() != Eigen::Success) return false;
      lm.V_inv_damped = llt.solve(Eigen::Matrix3d::Identity());
      // S −= W V⁻¹ Wᵀ (lower blocks) and rhs −= W V⁻¹ g, slot by slot.
      const int n_slots = static_cast<int>(lm.W.size());
      WV_.resize(static_cast<std::size_t>(n_slots));
      for (int a = 0; a < n_slots; ++a) WV_[a].noalias() = lm.W[a].lazyProduct(lm.V_inv_damped);
      for (int a = 0; a < n_slots; ++a) {
        const Variable& va = variables_[lm.slot_variables[a]];
        rhs_.segment(va.offset, va.tangent).noalias() -= (WV_[a].lazyProduct(lm.g)).topRows(va.tangent);
        for (int b = 0; b < n_slots; ++b) {
          const Variable& vb = variables_[lm.slot_variables[b]];
          if (vb.offset > va.offset) continue;
          if (va.tangent == 6 && vb.tangent == 6) {
            S_.block<6, 6>(va.offset, vb.offset).noalias() -= WV_[a].lazyProduct(lm.W[b].transpose());
          } else {
            const Eigen::Matrix<double, 6, 6> block = WV_[a].lazyProduct(lm.W[b].transpose());
            S_.block(va.offset, vb.offset, va.tangent, vb.tangent) -= block.topLeftCorner(va.tangent, vb.tangent);
          }
        }
      }
    }
    const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(S_);
    if (llt.info() != Eigen::Success) return false;
    delta_c_ = -llt.solve(rhs_);
    if (!delta_c_.allFinite()) return false;
    double g_delta = g_.dot(delta_c_);
    for (int i = 0; i < reduced_dims_; ++i) d_delta += clampDiagonal(H_(i, i)) * delta_c_(i) * delta_c_(i);
    delta_l_.resize(landmarks_.size());
    for (std::size_t l = 0; l < landmarks_.size(); ++l) {
      const Landmark& lm = landmarks_[l];
      Eigen::Vector3d b = -lm.g;
      for (std::size_t a = 0; a < lm.W.size(); ++a) {
        const Variable& va = variables_[lm.slot_variables[a]];
        b.noalias() -= lm.W[a].topRows(va.tangent).transpose() * delta_c_.segment(va.offset, va.tangent);
      }
      delta_l_[l] = lm.V_inv_damped * b;
      if (!delta_l_[l].allFinite()) return false;
      g_delta += lm.g.dot(delta_l_[l]);
      for (int k = 0; k < 3; ++k) d_delta += clampDiagonal(lm.V(k, k)) * delta_l_[l](k) * delta_l_[l](k);
    }
    model_decrease = 0.5 * mu * d_delta - 0.5 * g_delta;
    return true;
  }

  double stepNorm() const {
    double sq = delta_c_.squaredNorm();
    for (const Eigen::Vector3d& d : delta_l_) sq += d.squaredNorm();
    return std::sqrt(sq);
  }

  double gradientMaxNorm() const {
    double m = g_.size() ? g_.cwiseAbs().maxCoeff() : 0.0;
    for (const Landmark& lm : landmarks_) m = std::max(m, lm.g.cwiseAbs().maxCoeff());
    return m;
  }

  double parameterNorm() const {
    double sq = 0.0;
    for (const Variable& v : variables_)
      if (!v.constant) sq += Eigen::Map<const Eigen::VectorXd>(v.block, v.ambient).squaredNorm();
    return std::sqrt(sq);
  }

  void saveValues() {
    saved_.clear();
    for (const Variable& v : variables_)
      if (!v.constant) saved_.insert(saved_.end(), v.block, v.block + v.ambient);
  }

  void restoreValues() {
    std::size_t k = 0;
    for (const Variable& v : variables_) {
      if (v.constant) continue;
      std::copy(saved_.begin() + static_cast<std::ptrdiff_t>(k), saved_.begin() + static_cast<std::ptrdiff_t>(k + v.ambient),
                v.block);
      k += static_cast<std::size_t>(v.ambient);
    }
  }

  /// x ← x ⊞ δ (after saveValues()).
  void applyStep() {
    double moved[7];
    for (const Variable& v : variables_) {
      if (v.constant) continue;
      const double* d = v.landmark >= 0 ? delta_l_[v.landmark].data() : delta_c_.data() + v.offset;
      if (v.kind == BlockKind::kPose) {
        manifold_.Plus(v.block, d, moved);
        std::copy(moved, moved + v.ambient, v.block);
      } else {
        for (int k = 0; k < v.ambient; ++k) v.block[k] += d[k];
      }
    }
  }

 private:
  /// The GP projection's 2 × (4·6 + 3) Jacobian with fixed sizes; coefficient-wise products (the inner
  /// dimension is 2: a blocked matrix product would spend its time packing). Lower blocks only.
  void accumulateProjection(const Factor& f) {
    Eigen::Matrix<double, 2, 24> Jc;
    for (int b = 0; b < 4; ++b) {
      const Eigen::Map<const RowMatrix> J(jacobians_.data() + blockJacobian(f, b), 2,
                                          variables_[blockVariable(f, b)].ambient);
      Jc.middleCols<6>(6 * b) = J.leftCols<6>();
    }
    const Eigen::Map<const Eigen::Vector2d> r(residuals_.data() + f.residual_offset);
    const Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jl(jacobians_.data() + blockJacobian(f, 4));
    Landmark& lm = landmarks_[f.landmark];
    lm.V.noalias() += Jl.transpose().lazyProduct(Jl);
    lm.g.noalias() += Jl.transpose().lazyProduct(r);
    for (int i = 0; i < 4; ++i) {
      const int oi = variables_[blockVariable(f, i)].offset;
      const auto Ji = Jc.middleCols<6>(6 * i);
      g_.segment<6>(oi).noalias() += Ji.transpose().lazyProduct(r);
      lm.W[blockSlot(f, i)].noalias() += Ji.transpose().lazyProduct(Jl);
      for (int j = 0; j < 4; ++j) {
        const int oj = variables_[blockVariable(f, j)].offset;
        if (oj > oi) continue;
        H_.block<6, 6>(oi, oj).noalias() += Ji.transpose().lazyProduct(Jc.middleCols<6>(6 * j));
      }
    }
  }

  /// A linear prior's normal equations (LinearPriorFactor::normalEquations), lower blocks; with
  /// `with_information` false its gradient alone.
  void accumulateLinearPrior(const Factor& f, bool with_information = true) {
    f.linear_prior->normalEquations(f.entry->blocks.data(), prior_information_, prior_gradient_);
    int ci = 0;
    for (int i = 0; i < f.blocks; ++i) {
      const Variable& vi = variables_[blockVariable(f, i)];
      if (!vi.constant) {
        g_.segment(vi.offset, vi.tangent) += prior_gradient_.segment(ci, vi.tangent);
        int cj = 0;
        for (int j = 0; with_information && j < f.blocks; ++j) {
          const Variable& vj = variables_[blockVariable(f, j)];
          if (!vj.constant && vj.offset <= vi.offset)
            H_.block(vi.offset, vj.offset, vi.tangent, vj.tangent) += prior_information_.block(ci, cj, vi.tangent, vj.tangent);
          cj += vj.tangent;
        }
      }
      ci += vi.tangent;
    }
  }

  const ceres::Manifold& manifold_;
  std::vector<Variable> variables_;
  std::vector<Factor> factors_;
  std::vector<Landmark> landmarks_;
  int reduced_dims_ = 0;
  // The large buffers live in the workspace (WindowSolverWorkspace::Buffers) and keep their memory
  // between solves; every element read is written first in this solve.
  std::vector<double>& residuals_;
  std::vector<double>& jacobians_;
  std::vector<double>& saved_;
  std::vector<double>& factor_cost_;  ///< each factor's ½ρ(|r|²) of the latest evaluation
  std::vector<int>& block_variables_;         ///< per block of every factor (Factor::first): its variable
  std::vector<int>& block_jacobian_offsets_;  ///< its offset into jacobians_ (m × ambient, row-major); −1: constant
  std::vector<int>& block_slots_;             ///< its slot among its landmark's camera blocks, or −1
  std::vector<int> eval_order_;      ///< factor indices in evaluation order (grouped by first block)
  std::vector<int> bounds_;          ///< the ranges of eval_order_ evaluated by one thread each
  Eigen::MatrixXd& H_;
  Eigen::MatrixXd& S_;
  Eigen::VectorXd& g_;
  Eigen::VectorXd& rhs_;
  Eigen::VectorXd& delta_c_;
  std::vector<Eigen::Vector3d> delta_l_;
  std::vector<CameraLandmarkBlock> WV_;  ///< scratch: W V⁻¹ of one landmark
  Eigen::MatrixXd camera_jacobian_, camera_information_;  ///< scratch of a generic factor
  Eigen::VectorXd camera_gradient_;
  Eigen::MatrixXd prior_information_;  ///< scratch of a linear prior
  Eigen::VectorXd prior_gradient_;
};

}  // namespace

WindowSolverWorkspace::WindowSolverWorkspace() : buffers_(std::make_unique<Buffers>()) {}
WindowSolverWorkspace::~WindowSolverWorkspace() = default;

WindowSolverSummary solveWindow(const std::vector<FactorEntry>& factors, const std::map<double*, BlockKind>& kinds,
                                const std::set<const double*>& landmarks, const std::set<const double*>& constant,
                                const ceres::Manifold& pose_manifold, const WindowSolverOptions& options,
                                WindowSolverWorkspace* workspace) {
  const auto start = Clock::now();
  WindowSolverSummary summary;
  std::unique_ptr<WindowSolverWorkspace> own;  // a solve without a workspace of the caller's
  if (!workspace) {
    own = std::make_unique<WindowSolverWorkspace>();
    workspace = own.get();
  }
  ArrowProblem problem(factors, kinds, landmarks, constant, pose_manifold, workspace->buffers());
  summary.eliminated_landmarks = problem.eliminatedLandmarks();
  summary.reduced_dims = problem.reducedDims();
  summary.evaluation_threads = problem.evaluationThreads(options.threads);
  problem.splitEvaluation(summary.evaluation_threads);
  RangeWorkers workers(summary.evaluation_threads - 1);

  auto timed = [](double& total_ms, auto&& fn) {
    const auto t = Clock::now();
    const auto result = fn();
    total_ms += msSince(t);
    return result;
  };
  double cost = 0.0;
  if (!timed(summary.jacobians_ms, [&] { return problem.evaluate(true, cost, workers); })) {
    summary.valid_start = false;
    summary.total_ms = msSince(start);
    return summary;
  }
  summary.initial_cost = summary.final_cost = cost;
  summary.iterations = 1;
  timed(summary.linear_ms, [&] {
    problem.buildNormalEquations();
    return 0;
  });
  summary.linearizations = 1;
  double radius = options.initial_radius;
  double decrease_factor = 2.0;
  int steps_since_linearization = 0;  // steps taken since the Jacobians of H were evaluated
  bool jacobians_stale = false;       // the Jacobian buffer holds a rejected candidate's
  bool done = problem.gradientMaxNorm() <= options.gradient_tolerance;
  for (int iteration = 1; !done && iteration <= options.max_iterations; ++iteration) {
    if (options.max_time_s > 0.0 && msSince(start) >= 1e3 * options.max_time_s) break;
    summary.iterations = iteration + 1;
    double model_decrease = 0.0;
    const bool solved = timed(summary.linear_ms, [&] { return problem.solveStep(1.0 / radius, model_decrease); });
    if (!solved || !(model_decrease > 0.0)) {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (radius < 1e-32) break;
      continue;
    }
    if (problem.stepNorm() <= options.parameter_tolerance * (problem.parameterNorm() + options.parameter_tolerance))
      break;
    problem.saveValues();
    problem.applyStep();
    // The candidate is evaluated with its Jacobians (steps are mostly taken, and the linearization then
    // comes from this evaluation), except at the last iteration, where nothing would use them, and
    // between relinearizations (relinearize_every > 1), where only its gradient is rebuilt, through the
    // Jacobians of the linearization. H and g are kept apart from the evaluation buffers, so a rejected
    // candidate leaves them valid; a rejected candidate evaluated with Jacobians leaves the Jacobian
    // buffer at its values, so the next candidate relinearizes.
    const bool last = iteration == options.max_iterations;
    const bool relinearize =
        !last && (jacobians_stale || steps_since_linearization + 1 >= std::max(options.relinearize_every, 1));
    double candidate = 0.0;
    const bool valid = timed(relinearize ? summary.jacobians_ms : summary.residuals_ms, [&] {
      return problem.evaluate(relinearize, candidate, workers, !relinearize && !last);
    });
    if (valid && std::abs(cost - candidate) <= options.function_tolerance * cost) {
      problem.restoreValues();  // as Ceres: the function tolerance ends the solve before the step is taken
      break;
    }
    const double rho = valid ? (cost - candidate) / model_decrease : -1.0;
    if (!valid || rho <= options.min_relative_decrease) {
      if (relinearize) jacobians_stale = true;
      problem.restoreValues();
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (radius < 1e-32) break;
      continue;
    }
    ++summary.accepted_steps;
    radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
    decrease_factor = 2.0;
    cost = candidate;
    summary.final_cost = cost;
    if (last) break;
    timed(summary.linear_ms, [&] {
      if (relinearize) {
        problem.buildNormalEquations();
      } else {
        problem.buildGradient();
      }
      return 0;
    });
    if (relinearize) {
      steps_since_linearization = 0;
      jacobians_stale = false;
      ++summary.linearizations;
    } else {
      ++steps_since_linearization;
    }
    done = problem.gradientMaxNorm() <= options.gradient_tolerance;
  }
  summary.total_ms = msSince(start);
  return summary;
}

}  // namespace asynevo::backend
