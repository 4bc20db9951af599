#include "asynevo/backend/feature_track.hpp"

#include <algorithm>

#include "asynevo/core/time.hpp"

namespace asynevo::backend {

namespace {
bool earlier(const Observation& o, int64_t t) { return o.t_ns < t; }
}  // namespace

std::optional<Eigen::Vector2d> FeatureTrack::pointAt(int64_t t_ns) const {
  if (observations.empty() || t_ns < firstTime() || t_ns > lastTime()) return std::nullopt;
  auto it = std::lower_bound(observations.begin(), observations.end(), t_ns, earlier);
  if (it->t_ns == t_ns) return it->xn;
  const Observation& b = *it;
  const Observation& a = *std::prev(it);
  const double s = durationSeconds(a.t_ns, t_ns) / durationSeconds(a.t_ns, b.t_ns);
  return a.xn + s * (b.xn - a.xn);
}

bool FeatureTrack::observedIn(int64_t from_ns, int64_t to_ns) const {
  auto it = std::lower_bound(observations.begin(), observations.end(), from_ns, earlier);
  return it != observations.end() && it->t_ns <= to_ns;
}

std::size_t FeatureTrack::dropBefore(int64_t t_ns) {
  auto it = std::lower_bound(observations.begin(), observations.end(), t_ns, earlier);
  const auto n = static_cast<std::size_t>(it - observations.begin());
  observations.erase(observations.begin(), it);
  return n;
}

}  // namespace asynevo::backend
