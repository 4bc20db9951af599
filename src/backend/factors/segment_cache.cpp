#include "asynevo/backend/factors/segment_cache.hpp"

#include <algorithm>

#include "asynevo/backend/factors/pose_block.hpp"

namespace asynevo::backend {

std::shared_ptr<const gp::SegmentTerms> SegmentCache::terms(const double* pose_k, const double* pose_k1,
                                                            const double* vel_k1, bool with_jacobians,
                                                            int series_order) {
  std::array<double, kKeySize> key;
  std::copy(pose_k, pose_k + 7, key.begin());
  std::copy(pose_k1, pose_k1 + 7, key.begin() + 7);
  std::copy(vel_k1, vel_k1 + 6, key.begin() + 14);
  const std::lock_guard<std::mutex> lock(mutex_);
  // Exact comparison: the same values give the same terms; anything else is recomputed.
  if (terms_ && key == key_ && series_order == series_order_ && (terms_->with_jacobians || !with_jacobians)) {
    ++reused_;
    return terms_;
  }
  terms_ = std::make_shared<const gp::SegmentTerms>(gp::segmentTerms(
      poseFromBlock(pose_k), poseFromBlock(pose_k1), Eigen::Map<const gp::Vec6>(vel_k1), with_jacobians, series_order));
  key_ = key;
  series_order_ = series_order;
  ++computed_;
  return terms_;
}

}  // namespace asynevo::backend
