#pragma once
// GP projection factor: a feature measurement at time t ∈ [t_k, t_{k+1}] in normalized (undistorted)
// image coordinates, predicted through the GP-interpolated camera pose T(t) (gp/interpolation.hpp).
//
//   T_τ = T(t),  p_c = R_τᵀ (p_w − t_τ),  r = (π(p_c) − z)/σ,  π(p) = [p_x/p_z, p_y/p_z]
//   ∂r/∂δ_τ = (1/σ) Jπ [−I₃, p_c^],   ∂r/∂p_w = (1/σ) Jπ R_τᵀ
//   ∂r/∂{δ_k, ϖ_k, δ_{k+1}, ϖ_{k+1}} = ∂r/∂δ_τ · ∂δ_τ/∂(·)   (PoseInterpolator::chain)
// (reference/backend.md §4; docs/math/gp_backend.md §4.) Body = camera (pure event camera).
//
// Parameter blocks: {T_k (7), ϖ_k (6), T_{k+1} (7), ϖ_{k+1} (6), p_w (3)}. Evaluate returns false when
// the point is not in front of the camera (p_c,z ≤ min_depth), so Ceres rejects the step. The robust
// loss is not part of the factor: pass it to Problem::AddResidualBlock.

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include "asynevo/backend/factors/segment_cache.hpp"
#include "asynevo/gp/interpolation.hpp"

namespace asynevo::backend {

class GpProjectionFactor final : public ceres::SizedCostFunction<2, 7, 6, 7, 6, 3> {
 public:
  static constexpr double kDefaultMinDepth = 1e-6;

  /// `z` normalized image point; `weights` from gp::interpolationWeights(t − t_k, t_{k+1} − t_k);
  /// `sigma` measurement standard deviation in normalized units (pixel σ / focal length).
  GpProjectionFactor(const Eigen::Vector2d& z, const gp::InterpolationWeights& weights, double sigma,
                     double min_depth = kDefaultMinDepth, int series_order = gp::kDefaultSeriesOrder);
  /// Same, from int64-ns times (t_k ≤ t ≤ t_{k1}).
  GpProjectionFactor(const Eigen::Vector2d& z, int64_t t_ns, int64_t t_k_ns, int64_t t_k1_ns, double sigma,
                     double min_depth = kDefaultMinDepth, int series_order = gp::kDefaultSeriesOrder);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// Shares the knot-only interpolation terms with the other factors of the same segment (optional;
  /// the results are the same with or without).
  void setSegmentCache(std::shared_ptr<SegmentCache> cache) { cache_ = std::move(cache); }

  const Eigen::Vector2d& measurement() const { return z_; }
  const gp::InterpolationWeights& weights() const { return weights_; }

 private:
  Eigen::Vector2d z_;
  gp::InterpolationWeights weights_;
  double inv_sigma_;
  double min_depth_;
  int series_order_;
  std::shared_ptr<SegmentCache> cache_;
};

}  // namespace asynevo::backend
