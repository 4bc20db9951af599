#include "asynevo/eval/velocity_errors.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "asynevo/core/time.hpp"
#include "asynevo/eval/alignment.hpp"

namespace asynevo::eval {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// Body velocity of the ground truth at one pose (central difference of its neighbours).
struct GtVelocity {
  int64_t t_ns;
  Eigen::Vector3d v, w;
};

std::vector<GtVelocity> differentiate(const StampedTrajectory& gt, int64_t max_gap_ns) {
  std::vector<GtVelocity> out;
  for (std::size_t i = 1; i + 1 < gt.size(); ++i) {
    const StampedPose& a = gt[i - 1];
    const StampedPose& b = gt[i + 1];
    if (gt[i].t_ns - a.t_ns > max_gap_ns || b.t_ns - gt[i].t_ns > max_gap_ns || b.t_ns <= a.t_ns) continue;
    const double dt = nsToSeconds(b.t_ns - a.t_ns);
    const Eigen::Vector3d v_w = (b.p_w_c - a.p_w_c) / dt;
    const Eigen::AngleAxisd dR(a.q_w_c.conjugate() * b.q_w_c);  // R_a^T R_b, angle in [0, π]
    out.push_back({gt[i].t_ns, gt[i].q_w_c.conjugate() * v_w, dR.angle() * dR.axis() / dt});
  }
  return out;
}

double meanOf(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

}  // namespace

VelocityErrors computeVelocityErrors(const StampedTrajectory& gt, const std::vector<StampedTwist>& twists,
                                     double scale, int64_t max_gt_gap_ns) {
  if (!std::isfinite(scale) || !(scale > 0.0)) {
    throw EvalError(fmt::format("velocity error: the scale {} is not a positive number", scale));
  }
  if (max_gt_gap_ns <= 0) throw EvalError("velocity error: the maximum ground-truth gap must be > 0");
  for (std::size_t i = 1; i < gt.size(); ++i) {
    if (gt[i].t_ns < gt[i - 1].t_ns) {
      throw EvalError(
          fmt::format("velocity error: ground-truth pose {} (t = {:.3f} s) is earlier than the "
                      "previous pose",
                      i, nsToSeconds(gt[i].t_ns)));
    }
  }
  VelocityErrors r;
  r.scale = scale;
  r.est_twists = twists.size();
  const std::vector<GtVelocity> ref = differentiate(gt, max_gt_gap_ns);

  std::vector<double> lin, ang, speed, rate;
  std::vector<double> direction;  // angle between v_e and v_g per sample [deg]; NaN where v_e = 0
  for (const StampedTwist& tw : twists) {
    // First ground-truth sample at or after the twist's time.
    const auto hi = std::lower_bound(ref.begin(), ref.end(), tw.t_ns,
                                     [](const GtVelocity& g, int64_t t) { return g.t_ns < t; });
    if (hi == ref.end()) continue;
    Eigen::Vector3d v_g = hi->v, w_g = hi->w;
    if (hi->t_ns != tw.t_ns) {
      if (hi == ref.begin()) continue;
      const GtVelocity& lo = *(hi - 1);
      if (hi->t_ns - lo.t_ns > max_gt_gap_ns) continue;
      const double f = static_cast<double>(tw.t_ns - lo.t_ns) / static_cast<double>(hi->t_ns - lo.t_ns);
      v_g = (1.0 - f) * lo.v + f * hi->v;
      w_g = (1.0 - f) * lo.w + f * hi->w;
    }
    lin.push_back((scale * tw.v_c - v_g).norm());
    ang.push_back((tw.w_c - w_g).norm() * kRadToDeg);
    direction.push_back(tw.v_c.norm() > 0.0 ? std::atan2(tw.v_c.cross(v_g).norm(), tw.v_c.dot(v_g)) * kRadToDeg
                                            : std::numeric_limits<double>::quiet_NaN());
    speed.push_back(v_g.norm());
    rate.push_back(w_g.norm() * kRadToDeg);
    r.t_s.push_back(nsToSeconds(tw.t_ns));
  }
  r.samples = lin.size();
  r.linear_mps = computeStats(lin);
  r.angular_dps = computeStats(ang);
  r.mean_gt_speed_mps = meanOf(speed);
  r.mean_gt_rate_dps = meanOf(rate);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.linear_rmse_perc = r.mean_gt_speed_mps > 0.0 ? 100.0 * r.linear_mps.rmse / r.mean_gt_speed_mps : nan;
  r.angular_rmse_perc = r.mean_gt_rate_dps > 0.0 ? 100.0 * r.angular_dps.rmse / r.mean_gt_rate_dps : nan;
  std::vector<double> angles;
  std::size_t reversed = 0;
  for (std::size_t i = 0; i < direction.size(); ++i) {
    if (!(speed[i] >= kDirectionMinSpeedFraction * r.mean_gt_speed_mps) || !std::isfinite(direction[i])) continue;
    angles.push_back(direction[i]);
    reversed += direction[i] > 90.0;
  }
  r.direction_deg = computeStats(angles);
  r.reversed_fraction = angles.empty() ? nan : static_cast<double>(reversed) / static_cast<double>(angles.size());
  return r;
}

std::string velocitiesBesideEstimate(const std::string& est_path) {
  const std::filesystem::path p = std::filesystem::path(est_path).parent_path() / "velocities.txt";
  std::error_code ec;
  return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

}  // namespace asynevo::eval
