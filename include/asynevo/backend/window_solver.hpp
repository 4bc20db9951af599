#pragma once
// The window's own Levenberg–Marquardt solver (backend.window_solver: builtin). The window's normal
// equations have the arrow shape of bundle adjustment (paper §IV; reference/backend.md §6): every
// projection couples one landmark (3) with the four blocks of one knot interval (2 × (pose 6 + twist 6)),
// the WNOA priors couple neighbouring knots, and the marginalization prior couples the oldest knots.
// The solver forms H = JᵀJ and g = Jᵀr from each factor's own Jacobians (robust weights folded in as
// in factor_graph.hpp), eliminates every landmark that no factor couples to another landmark with its
// 3×3 block (Schur complement), solves the reduced knot system by a dense Cholesky factorization and
// back-substitutes the landmarks.
//
// The iteration is Ceres's Levenberg–Marquardt (Ceres Solver documentation, "Non-linear Least Squares",
// Levenberg–Marquardt; Nielsen, "Damping parameter in Marquardt's method", 1999): step (H + D/Δ)δ = −g
// with D = diag(H) clamped to [1e-6, 1e32]; gain ratio ρ = actual / model cost decrease, the model
// decrease being ½δᵀ(D/Δ)δ − ½gᵀδ; a step with ρ > 1e-3 is taken and Δ ← Δ / max(1/3, 1 − (2ρ − 1)³),
// otherwise Δ ← Δ/ν, ν ← 2ν. A step at which a factor refuses to evaluate (a point behind the camera) is
// rejected. Stops as Ceres does: max iterations, |Δcost| ≤ function_tolerance · cost, max |g| ≤
// gradient_tolerance, |δ| ≤ parameter_tolerance (|x| + parameter_tolerance), or the wall-time cap.
// Deterministic: the result depends only on the factor order and the values. The factors can be
// evaluated on several threads (`threads`), with the same result bit for bit; the rest is sequential.

#include <ceres/manifold.h>

#include <map>
#include <memory>
#include <set>
#include <vector>

#include "asynevo/backend/factor_graph.hpp"

namespace asynevo::backend {

struct WindowSolverOptions {
  int max_iterations = 5;
  double max_time_s = 0.0;  ///< wall-time cap (0: none); makes the result depend on the machine
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_radius = 1e4;
  double min_relative_decrease = 1e-3;
  /// Threads evaluating the factors (residuals, Jacobians); the result does not depend on it.
  int threads = 1;
  /// The Jacobians and the normal equations are evaluated at every k-th step taken; in between, a step
  /// reuses them with the gradient at the new values (a chord step). 1: every step (Levenberg–Marquardt).
  int relinearize_every = 1;
};

struct WindowSolverSummary {
  /// As Ceres counts them (Summary::iterations.size()): the evaluation at the start is iteration 0.
  int iterations = 0;
  int accepted_steps = 0;
  int linearizations = 0;  ///< evaluations whose Jacobians built the normal equations (the start's included)
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool valid_start = true;  ///< false: a factor refused to evaluate at the start; nothing was changed
  int eliminated_landmarks = 0;
  int reduced_dims = 0;  ///< size of the dense system after the elimination
  int evaluation_threads = 1;  ///< threads the factors were evaluated on (`threads`, fewer for few factors)
  double residuals_ms = 0.0, jacobians_ms = 0.0, linear_ms = 0.0, total_ms = 0.0;
};

/// The large buffers of a solve (residuals, Jacobians, the knot system), kept from one solve to the next
/// by whoever solves repeatedly (the sliding window keeps one), so that a solve reuses their memory
/// instead of asking the allocator for megabytes that come back as fresh pages every time. The result
/// does not depend on it.
class WindowSolverWorkspace {
 public:
  struct Buffers;  ///< defined in window_solver.cpp
  WindowSolverWorkspace();
  ~WindowSolverWorkspace();
  WindowSolverWorkspace(const WindowSolverWorkspace&) = delete;
  WindowSolverWorkspace& operator=(const WindowSolverWorkspace&) = delete;
  Buffers& buffers() { return *buffers_; }

 private:
  std::unique_ptr<Buffers> buffers_;
};

/// Minimizes Σ ½ρ(|rᵢ|²) over the blocks of `factors` in place. `kinds`: the kind of every block (pose
/// blocks move through `pose_manifold`, whose tangent Jacobian is the first 6 of the 7 ambient columns);
/// `landmarks`: the blocks that may be eliminated (3-vectors); `constant`: blocks held fixed.
/// `workspace`: buffers to reuse (none: the solve allocates its own).
WindowSolverSummary solveWindow(const std::vector<FactorEntry>& factors, const std::map<double*, BlockKind>& kinds,
                                const std::set<const double*>& landmarks, const std::set<const double*>& constant,
                                const ceres::Manifold& pose_manifold, const WindowSolverOptions& options,
                                WindowSolverWorkspace* workspace = nullptr);

}  // namespace asynevo::backend
