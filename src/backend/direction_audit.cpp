#include "asynevo/backend/direction_audit.hpp"

#include <algorithm>

#include "asynevo/backend/depth_reversal.hpp"
#include "upper_median.hpp"
#include "view_geometry.hpp"

namespace asynevo::backend {

std::optional<ReversalCheck> auditDirection(const Trajectory& window, const TrackMap& tracks, int64_t t_a_ns,
                                            int64_t t_b_ns, double focal, double cauchy_px, double min_parallax_px,
                                            int min_features) {
  if (!window.covers(t_a_ns) || !window.covers(t_b_ns) || t_b_ns <= t_a_ns) return std::nullopt;
  std::vector<lie::Vec3> a, b;
  for (const auto& [id, track] : tracks) {
    const auto x_a = track.pointAt(t_a_ns);
    const auto x_b = x_a ? track.pointAt(t_b_ns) : std::nullopt;
    if (!x_b) continue;
    a.push_back(view_geometry::ray(x_a->x(), x_a->y()));
    b.push_back(view_geometry::ray(x_b->x(), x_b->y()));
  }
  if (static_cast<int>(a.size()) < std::max(min_features, 5)) return std::nullopt;
  // x_b = R_b_a x_a + t_b_a with T_b_a = T_w_b⁻¹ T_w_a.
  const lie::SE3 T_b_a = window.pose(t_b_ns).inverse() * window.pose(t_a_ns);
  if (!(T_b_a.translation().norm() > 1e-9)) return std::nullopt;
  std::vector<double> parallax;
  for (std::size_t i = 0; i < a.size(); ++i)
    parallax.push_back(view_geometry::angleBetween(T_b_a.rotation() * a[i], b[i]) * focal);
  const double median_parallax = upperMedian(parallax);
  if (median_parallax < min_parallax_px) return std::nullopt;
  const TwoViewMotion motion{T_b_a.rotation(), T_b_a.translation().normalized()};
  const auto reversal = findDepthReversal(motion, a, b, focal, cauchy_px);
  ReversalCheck check;
  check.t_a_ns = t_a_ns;
  check.t_b_ns = t_b_ns;
  check.method = "audit";
  check.features = static_cast<int>(a.size());
  check.parallax_px = median_parallax;
  // The window's own motion, not its refinement on the chirality cost, is what is audited: the cost is
  // the refined one (the nearest minimum), the direction the window's.
  check.cost = reversal.given_cost;
  check.t_b_a = motion.t_b_a;
  check.found = reversal.reversed.has_value();
  if (check.found) {
    check.reversed_cost = reversal.reversed_cost;
    check.reversed_t_b_a = reversal.reversed->t_b_a;
  }
  return check;
}

}  // namespace asynevo::backend
