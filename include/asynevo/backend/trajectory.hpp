#pragma once
// The continuous-time trajectory: knots {T_w_c,k, ϖ_k} keyed by int64 ns, queried anywhere between the
// first and the newest knot by GP interpolation (gp/interpolation.hpp), beyond it by constant-velocity
// extrapolation (prediction only). Knot values live in Ceres-ready arrays at stable addresses (std::map
// nodes never move), so a solver can use them as parameter blocks directly.

#include <array>
#include <cstdint>
#include <map>
#include <optional>

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

struct Knot {
  int64_t t_ns = 0;
  std::array<double, kPoseSize> pose{};          ///< [t_x t_y t_z q_x q_y q_z q_w], T_w_c
  std::array<double, kVelocitySize> velocity{};  ///< ϖ = [v; ω], body frame

  lie::SE3 T_w_c() const { return poseFromBlock(pose.data()); }
  lie::Vec6 twist() const { return Eigen::Map<const lie::Vec6>(velocity.data()); }
  void set(const lie::SE3& T_w_c, const lie::Vec6& w) {
    poseToBlock(T_w_c, pose.data());
    Eigen::Map<lie::Vec6>(velocity.data()) = w;
  }
};

class Trajectory {
 public:
  using KnotMap = std::map<int64_t, Knot>;

  /// Adds a knot (times must be unique; not necessarily newest). Returns a reference that stays valid
  /// until the knot is removed.
  Knot& add(int64_t t_ns, const lie::SE3& T_w_c, const lie::Vec6& w);
  /// Appends a knot at t_ns > newest, predicted from the newest knot at constant velocity.
  Knot& extendTo(int64_t t_ns);
  void remove(int64_t t_ns);

  bool empty() const { return knots_.empty(); }
  std::size_t size() const { return knots_.size(); }
  int64_t oldestTime() const { return knots_.begin()->first; }
  int64_t newestTime() const { return knots_.rbegin()->first; }
  const KnotMap& knots() const { return knots_; }
  KnotMap& knots() { return knots_; }
  Knot* find(int64_t t_ns);
  const Knot* find(int64_t t_ns) const;

  /// The two knots around t: t_k ≤ t < t_{k+1}; t equal to the newest knot time uses the last segment.
  /// nullopt when t is outside [oldest, newest] or there are fewer than two knots.
  std::optional<std::pair<const Knot*, const Knot*>> segment(int64_t t_ns) const;

  /// True when t lies in [oldest, newest] (interpolation possible).
  bool covers(int64_t t_ns) const { return !knots_.empty() && t_ns >= oldestTime() && t_ns <= newestTime(); }

  /// T_w_c(t): the knot itself at a knot time, GP interpolation inside, constant-velocity extrapolation
  /// after the newest knot. Throws std::out_of_range before the oldest knot or on an empty trajectory.
  lie::SE3 pose(int64_t t_ns) const;
  /// ϖ(t), same rules.
  lie::Vec6 velocity(int64_t t_ns) const;

 private:
  KnotMap knots_;
};

}  // namespace asynevo::backend
