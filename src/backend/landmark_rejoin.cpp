#include "asynevo/backend/landmark_rejoin.hpp"

namespace asynevo::backend {

namespace {

/// True when p_w projects within max_error of every view, at a depth of at least min_depth.
bool fitsEveryView(const Eigen::Vector3d& p_w, const std::vector<TriangulationView>& views,
                   const RejoinOptions& options) {
  for (const TriangulationView& v : views) {
    const Eigen::Vector3d p_c = v.T_w_c.inverse() * p_w;
    if (!(p_c.z() >= options.min_depth)) return false;
    if ((p_c.head<2>() / p_c.z() - v.xn).norm() > options.max_error) return false;
  }
  return true;
}

}  // namespace

RejoinMatch findRejoinLandmark(const std::vector<TriangulationView>& views, int64_t first_ns, const TrackMap& tracks,
                               const RejoinOptions& options) {
  RejoinMatch match;
  if (views.empty() || options.max_error <= 0) return match;
  for (const auto& [key, track] : tracks) {
    if (!track.triangulated || track.observations.empty() || track.lastTime() >= first_ns)
      continue;
    if (first_ns - track.lastTime() > options.max_gap_ns) continue;
    if (!fitsEveryView(Eigen::Map<const Eigen::Vector3d>(track.p_w.data()), views, options)) continue;
    ++match.candidates_fitting;
    match.key = key;
  }
  if (match.candidates_fitting != 1) match.key.reset();
  return match;
}

}  // namespace asynevo::backend
