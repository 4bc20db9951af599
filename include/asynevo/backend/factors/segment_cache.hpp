#pragma once
// The knot-only terms of the GP interpolation (gp::SegmentTerms: Log, inverse Jacobians, the series
// derivative M) shared by the projection factors of one segment. Ceres evaluates every factor of a
// segment at the same knot values, so the terms are computed once per segment and evaluation point
// instead of once per measurement (~20 % of the backend's time before). The cache is keyed on the
// values themselves (T_k, T_{k+1}, ϖ_{k+1}), not on pointers (Ceres evaluates trial points from its own
// buffers), and returns exactly what gp::segmentTerms would: results are bit-identical with or without it.
// Thread-safe (Ceres may evaluate residual blocks on several threads).

#include <array>
#include <memory>
#include <mutex>

#include "asynevo/gp/interpolation.hpp"

namespace asynevo::backend {

class SegmentCache {
 public:
  /// Terms at the given blocks (pose, pose, velocity: 7, 7, 6 doubles); with_jacobians as in
  /// gp::segmentTerms (a cached entry without Jacobians is recomputed when they are asked for). Shared,
  /// not copied: an entry is never changed, a recomputation makes a new one.
  std::shared_ptr<const gp::SegmentTerms> terms(const double* pose_k, const double* pose_k1, const double* vel_k1,
                                                bool with_jacobians, int series_order);

  /// How often the terms were computed and how often they were reused (for tests and benchmarks).
  uint64_t computed() const { return computed_; }
  uint64_t reused() const { return reused_; }

 private:
  static constexpr int kKeySize = 7 + 7 + 6;
  std::mutex mutex_;
  int series_order_ = 0;
  std::array<double, kKeySize> key_{};
  std::shared_ptr<const gp::SegmentTerms> terms_;  ///< null until the first call
  uint64_t computed_ = 0;
  uint64_t reused_ = 0;
};

}  // namespace asynevo::backend
