#include "asynevo/backend/landmark_rejoin.hpp"

namespace asynevo::backend {

namespace {

/// The views' mean offset from the projection of p_w when p_w projects within max_error of every view,
/// at a depth of at least min_depth; nullopt otherwise.
std::optional<Eigen::Vector2d> offsetIfFitsEveryView(const Eigen::Vector3d& p_w,
                                                     const std::vector<TriangulationView>& views,
                                                     const RejoinOptions& options) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const TriangulationView& v : views) {
    const Eigen::Vector3d p_c = v.T_w_c.inverse() * p_w;
    if (!(p_c.z() >= options.min_depth)) return std::nullopt;
    const Eigen::Vector2d offset = v.xn - p_c.head<2>() / p_c.z();
    if (offset.norm() > options.max_error) return std::nullopt;
    sum += offset;
  }
  return sum / static_cast<double>(views.size());
}

}  // namespace

RejoinMatch findRejoinLandmark(const std::vector<TriangulationView>& views, int64_t first_ns,
                               const TrackMap& tracks, const RejoinOptions& options) {
  RejoinMatch match;
  if (views.empty() || options.max_error <= 0) return match;
  for (const auto& [key, track] : tracks) {
    if (!track.triangulated || track.observations.empty() || track.lastTime() >= first_ns) continue;
    if (first_ns - track.lastTime() > options.max_gap_ns) continue;
    const Eigen::Map<const Eigen::Vector3d> p_w(track.p_w.data());
    const auto offset = offsetIfFitsEveryView(p_w, views, options);
    if (!offset) continue;
    ++match.candidates_fitting;
    match.key = key;
    match.offset = *offset;
  }
  if (match.candidates_fitting != 1) {
    match.key.reset();
    match.offset.setZero();
  }
  return match;
}

}  // namespace asynevo::backend
