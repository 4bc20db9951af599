#pragma once
// The linear velocity written with each final knot, from the final poses of its segment
// (docs/method/backend.md, "The velocity output"): a central difference over ±span knots. The GP's own
// knot velocity follows the measurements of one knot interval; its translational part, weakly observed
// by a monocular camera over 50 ms and loosely held by the WNOA prior, is noisier than the positions it
// connects. The angular part stays the GP's: rotation is observed directly, and a difference over
// ±span knots would smooth fast turns away.

#include <deque>
#include <vector>

#include "asynevo/backend/trajectory.hpp"

namespace asynevo::backend {

/// For knot i, from the final poses of knots a = i − s and b = i + s of its segment (fewer where the
/// segment ends, one-sided at its ends): v = R_iᵀ (p_b − p_a) / (t_b − t_a), the body-frame linear
/// velocity of the knot state (ϖ = [v; ω], T⁻¹Ṫ = ϖ^), as asynevo eval differentiates the ground truth.
/// A knot's velocity needs the s knots after it: the knots leave s knots late, and the rest when the
/// segment ends. span 0 passes the knots on at once with their GP velocity.
class VelocityFromPoses {
 public:
  explicit VelocityFromPoses(int span);

  /// A final knot of the current segment (times increasing); appends to `out` the knots whose velocity
  /// is now known.
  void push(const Knot& knot, std::vector<Knot>& out);
  /// The segment ended: appends every knot still held, with the neighbours the segment has.
  void flush(std::vector<Knot>& out);

 private:
  void emit(std::size_t i, std::vector<Knot>& out) const;

  int span_;
  std::deque<Knot> knots_;  ///< the segment's latest knots: up to span_ emitted ones, then the held ones
  std::size_t held_ = 0;    ///< the newest held_ of knots_ are not emitted yet
};

}  // namespace asynevo::backend
