#include "asynevo/backend/velocity_from_poses.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>

#include "asynevo/core/time.hpp"

namespace asynevo::backend {

VelocityFromPoses::VelocityFromPoses(int span) : span_(span) {
  if (span < 0) throw std::invalid_argument("VelocityFromPoses: the span must be >= 0");
}

void VelocityFromPoses::push(const Knot& knot, std::vector<Knot>& out) {
  if (span_ == 0) {
    out.push_back(knot);
    return;
  }
  knots_.push_back(knot);
  ++held_;
  // The oldest held knot has its span_ successors now: emit it.
  if (held_ > static_cast<std::size_t>(span_)) {
    emit(knots_.size() - held_, out);
    --held_;
  }
  // Keep span_ emitted knots as the predecessors of the next one.
  while (knots_.size() > held_ + static_cast<std::size_t>(span_)) knots_.pop_front();
}

void VelocityFromPoses::flush(std::vector<Knot>& out) {
  for (; held_ > 0; --held_) emit(knots_.size() - held_, out);
  knots_.clear();
}

void VelocityFromPoses::emit(std::size_t i, std::vector<Knot>& out) const {
  const std::size_t s = static_cast<std::size_t>(span_);
  const std::size_t a = i >= s ? i - s : 0;
  const std::size_t b = std::min(i + s, knots_.size() - 1);
  Knot k = knots_[i];
  if (b > a) {
    const Eigen::Map<const Eigen::Vector3d> p_a(knots_[a].pose.data()), p_b(knots_[b].pose.data());
    const double dt = nsToSeconds(knots_[b].t_ns - knots_[a].t_ns);
    // The pose stays as it is, bit for bit, and so does the angular velocity.
    Eigen::Map<Eigen::Vector3d>(k.velocity.data()) = k.T_w_c().rotation().transpose() * (p_b - p_a) / dt;
  }
  out.push_back(k);
}

}  // namespace asynevo::backend
