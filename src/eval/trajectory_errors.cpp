#include "asynevo/eval/trajectory_errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace asynevo::eval {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// Rotation angle (rad) as the norm of rpg's logmap_so3 (transformations.py): the arccos branch
/// away from the identity, its series (0.5 − (tr−3)²/12)·‖vee(R − Rᵀ)‖ near it, and the θ = π branch.
double logmapAngle(const Eigen::Matrix3d& R) {
  const double tr = R.trace();
  if (std::fabs(tr + 1.0) < 1e-10) {
    Eigen::Vector3d omega;
    if (std::fabs(R(2, 2) + 1.0) > 1e-10) {
      omega = M_PI / std::sqrt(2.0 + 2.0 * R(2, 2)) * Eigen::Vector3d(R(0, 2), R(1, 2), 1.0 + R(2, 2));
    } else if (std::fabs(R(1, 1) + 1.0) > 1e-10) {
      omega = M_PI / std::sqrt(2.0 + 2.0 * R(1, 1)) * Eigen::Vector3d(R(0, 1), 1.0 + R(1, 1), R(2, 1));
    } else {
      omega = M_PI / std::sqrt(2.0 + 2.0 * R(0, 0)) * Eigen::Vector3d(1.0 + R(0, 0), R(1, 0), R(2, 0));
    }
    return omega.norm();
  }
  const double tr_3 = tr - 3.0;
  double magnitude;
  if (tr_3 < -1e-7) {
    const double theta = std::acos(std::clamp((tr - 1.0) / 2.0, -1.0, 1.0));
    magnitude = theta / (2.0 * std::sin(theta));
  } else {
    magnitude = 0.5 - tr_3 * tr_3 / 12.0;
  }
  return magnitude * Eigen::Vector3d(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)).norm();
}

/// Rotation angle (deg) as rpg's compute_angle: arccos(clip((tr − 1)/2, −1, 1)).
double angleDeg(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0)) * kRadToDeg;
}

/// Yaw, pitch, roll of R = Rz(yaw)·Ry(pitch)·Rx(roll) ("rzyx" Euler angles in transformations.py).
Eigen::Vector3d yawPitchRoll(const Eigen::Matrix3d& R) {
  const double eps = std::numeric_limits<double>::epsilon() * 4.0;
  const double cy = std::sqrt(R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0));
  if (cy > eps) {
    return {std::atan2(R(1, 0), R(0, 0)), std::atan2(-R(2, 0), cy), std::atan2(R(2, 1), R(2, 2))};
  }
  return {0.0, std::atan2(-R(2, 0), cy), std::atan2(-R(1, 2), R(1, 1))};
}

/// (start, end) pairs: for each start, the end closest to d_start + length within max_dist_diff.
std::vector<std::pair<std::size_t, std::size_t>> comparisonPairs(const std::vector<double>& d, double length,
                                                                 double max_dist_diff) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const auto begin = d.begin();
  for (std::size_t idx = 0; idx < d.size(); ++idx) {
    const double target = d[idx] + length;
    // d is non-decreasing, so |d_j − target| falls, then rises. The minimum (first index on ties,
    // as a forward scan with a strict '<' keeps it) is the first index holding the largest value
    // below target, or the first index at or above it.
    const auto above = std::lower_bound(begin + static_cast<std::ptrdiff_t>(idx), d.end(), target);
    std::ptrdiff_t best = -1;
    double error = max_dist_diff;
    if (above != begin + static_cast<std::ptrdiff_t>(idx)) {
      const double below_value = *(above - 1);
      const auto first_below = std::lower_bound(begin + static_cast<std::ptrdiff_t>(idx), above, below_value);
      const double e = std::fabs(below_value - target);
      if (e < error) {
        best = first_below - begin;
        error = e;
      }
    }
    if (above != d.end()) {
      const double e = std::fabs(*above - target);
      if (e < error) best = above - begin;
    }
    if (best >= 0) pairs.emplace_back(idx, static_cast<std::size_t>(best));
  }
  return pairs;
}

}  // namespace

AbsoluteErrors computeAbsoluteErrors(const PosePairs& pairs, const Similarity& alignment) {
  AbsoluteErrors out;
  const std::size_t n = pairs.size();
  out.trans_m.reserve(n);
  out.rot_deg.reserve(n);
  out.scale_perc.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p_aligned = alignment.apply(pairs.p_est[i]);
    out.trans_m.push_back((pairs.p_gt[i] - p_aligned).norm());
    const Eigen::Matrix3d R_aligned = alignment.rotation * pairs.R_est[i];
    out.rot_deg.push_back(logmapAngle(R_aligned * pairs.R_gt[i].transpose()) * kRadToDeg);
    // rpg computes "motion" with np.diff(p, 0), which is p itself: the ratio of the distances
    // from the world origin.
    out.scale_perc.push_back(std::fabs((p_aligned.norm() / pairs.p_gt[i].norm() - 1.0) * 100.0));
  }
  out.trans = computeStats(out.trans_m);
  out.rot = computeStats(out.rot_deg);
  out.scale = computeStats(out.scale_perc);
  return out;
}

std::vector<double> distancesFromStart(const std::vector<Eigen::Vector3d>& positions) {
  std::vector<double> d;
  d.reserve(positions.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (i > 0) {
      const Eigen::Vector3d delta = positions[i] - positions[i - 1];
      sum += std::sqrt(delta.x() * delta.x() + delta.y() * delta.y() + delta.z() * delta.z());
    }
    d.push_back(sum);
  }
  return d;
}

std::vector<std::size_t> comparisonIndices(const std::vector<double>& distances, double length,
                                           double max_dist_diff) {
  std::vector<std::size_t> ends;
  for (const auto& [start, end] : comparisonPairs(distances, length, max_dist_diff)) ends.push_back(end);
  return ends;
}

std::vector<double> lengthsFromPercentages(double path_length, const std::vector<double>& percentages) {
  std::vector<double> lengths;
  for (double pct : percentages) lengths.push_back(std::trunc(pct * path_length * 100.0) / 100.0);
  return lengths;
}

RelativeErrors computeRelativeErrors(const PosePairs& pairs, const std::vector<double>& distances,
                                     double length, double scale, const RelativeErrorOptions& options) {
  RelativeErrors out;
  out.length_m = length;
  out.max_dist_diff_m = 0.2 * length;
  const auto found = comparisonPairs(distances, length, out.max_dist_diff_m);
  if (found.size() < 2) {  // rpg: "Too few samples! Will not compute."
    out.too_few = true;
    return out;
  }
  for (std::size_t k = 0; k < found.size(); ++k) {
    const std::size_t i = options.rpg_start_indexing ? k : found[k].first;
    const std::size_t j = found[k].second;
    if (i != found[k].first) ++out.shifted_starts;
    // Estimate's relative motion, translation scaled by the alignment scale.
    const Eigen::Matrix3d R_c = pairs.R_est[i].transpose() * pairs.R_est[j];
    const Eigen::Vector3d t_c = scale * (pairs.R_est[i].transpose() * (pairs.p_est[j] - pairs.p_est[i]));
    // Ground truth's relative motion.
    const Eigen::Matrix3d R_m = pairs.R_gt[i].transpose() * pairs.R_gt[j];
    const Eigen::Vector3d t_m = pairs.R_gt[i].transpose() * (pairs.p_gt[j] - pairs.p_gt[i]);
    // Error (T_m)⁻¹ T_c, then rotated into the world frame by the estimate's rotation at j.
    const Eigen::Matrix3d R_err = R_m.transpose() * R_c;
    const Eigen::Vector3d t_err = R_m.transpose() * (t_c - t_m);
    const Eigen::Matrix3d R_err_w = pairs.R_est[j] * R_err * pairs.R_est[j].transpose();
    const double trans = (pairs.R_est[j] * t_err).norm();
    const double rot = angleDeg(R_err_w);
    const Eigen::Vector3d ypr = yawPitchRoll(R_err_w);
    out.start.push_back(i);
    out.end.push_back(j);
    out.trans_m.push_back(trans);
    out.trans_perc.push_back(trans / length * 100.0);
    out.rot_deg.push_back(rot);
    out.yaw_deg.push_back(std::fabs(ypr.x()) * kRadToDeg);
    out.gravity_deg.push_back(std::sqrt(ypr.y() * ypr.y() + ypr.z() * ypr.z()) * kRadToDeg);
    out.rot_deg_per_m.push_back(rot / length);
  }
  computeRelativeStats(out);
  return out;
}

void computeRelativeStats(RelativeErrors& e) {
  e.trans = computeStats(e.trans_m);
  e.trans_perc_stats = computeStats(e.trans_perc);
  e.rot = computeStats(e.rot_deg);
  e.yaw = computeStats(e.yaw_deg);
  e.gravity = computeStats(e.gravity_deg);
  e.rot_per_m = computeStats(e.rot_deg_per_m);
}

}  // namespace asynevo::eval
