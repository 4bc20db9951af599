#include "asynevo/backend/trajectory.hpp"

#include <stdexcept>

#include "asynevo/core/time.hpp"
#include "asynevo/gp/interpolation.hpp"

namespace asynevo::backend {

Knot& Trajectory::add(int64_t t_ns, const lie::SE3& T_w_c, const lie::Vec6& w) {
  auto [it, inserted] = knots_.try_emplace(t_ns);
  if (!inserted) throw std::logic_error("Trajectory::add: a knot already exists at this time");
  it->second.t_ns = t_ns;
  it->second.set(T_w_c, w);
  return it->second;
}

Knot& Trajectory::extendTo(int64_t t_ns) {
  if (knots_.empty() || t_ns <= newestTime()) throw std::logic_error("Trajectory::extendTo: not after the newest knot");
  const Knot& last = knots_.rbegin()->second;
  const lie::Vec6 w = last.twist();
  return add(t_ns, last.T_w_c() * lie::se3::exp(durationSeconds(last.t_ns, t_ns) * w), w);
}

void Trajectory::remove(int64_t t_ns) { knots_.erase(t_ns); }

Knot* Trajectory::find(int64_t t_ns) {
  auto it = knots_.find(t_ns);
  return it == knots_.end() ? nullptr : &it->second;
}

const Knot* Trajectory::find(int64_t t_ns) const {
  auto it = knots_.find(t_ns);
  return it == knots_.end() ? nullptr : &it->second;
}

std::optional<std::pair<const Knot*, const Knot*>> Trajectory::segment(int64_t t_ns) const {
  if (knots_.size() < 2 || !covers(t_ns)) return std::nullopt;
  auto next = knots_.upper_bound(t_ns);  // first knot strictly after t
  if (next == knots_.end()) --next;      // t == newest: last segment
  auto prev = std::prev(next);
  return std::make_pair(&prev->second, &next->second);
}

namespace {

gp::PoseInterpolator interpolatorAt(const Knot& a, const Knot& b, int64_t t_ns) {
  const double dt = durationSeconds(a.t_ns, b.t_ns);
  return gp::PoseInterpolator(a.T_w_c(), a.twist(), b.T_w_c(), b.twist(),
                              gp::interpolationWeights(durationSeconds(a.t_ns, t_ns), dt), /*with_jacobians=*/false);
}

}  // namespace

lie::SE3 Trajectory::pose(int64_t t_ns) const {
  if (knots_.empty() || t_ns < oldestTime()) throw std::out_of_range("Trajectory::pose: before the first knot");
  if (const Knot* k = find(t_ns)) return k->T_w_c();
  if (t_ns > newestTime()) {
    const Knot& last = knots_.rbegin()->second;
    return last.T_w_c() * lie::se3::exp(durationSeconds(last.t_ns, t_ns) * last.twist());
  }
  const auto [a, b] = *segment(t_ns);
  return interpolatorAt(*a, *b, t_ns).pose();
}

lie::Vec6 Trajectory::velocity(int64_t t_ns) const {
  if (knots_.empty() || t_ns < oldestTime()) throw std::out_of_range("Trajectory::velocity: before the first knot");
  if (const Knot* k = find(t_ns)) return k->twist();
  if (t_ns > newestTime()) return knots_.rbegin()->second.twist();
  const auto [a, b] = *segment(t_ns);
  return gp::interpolateVelocity(interpolatorAt(*a, *b, t_ns), a->twist());
}

}  // namespace asynevo::backend
