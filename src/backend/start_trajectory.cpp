#include "asynevo/backend/start_trajectory.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "asynevo/core/time.hpp"
#include "asynevo/lie/se3.hpp"
#include "view_geometry.hpp"

namespace asynevo::backend {

Trajectory constantTwistTrajectory(const InitResult& motion, int64_t t_end_ns, int64_t knot_dt_ns) {
  const double span_s = durationSeconds(motion.t_a_ns, motion.t_b_ns);
  const lie::SE3 T_a_b(motion.T_a_b.rotation(), motion.T_a_b.translation() * span_s);
  const lie::Vec6 w = lie::se3::log(T_a_b) / span_s;
  Trajectory trajectory;
  for (int64_t t = motion.t_a_ns; t <= t_end_ns; t += knot_dt_ns) {
    trajectory.add(t, lie::se3::exp(durationSeconds(motion.t_a_ns, t) * w), w);
  }
  return trajectory;
}

lie::Vec3 startTravelDirection(const InitResult& motion) {
  const double span_s = durationSeconds(motion.t_a_ns, motion.t_b_ns);
  const lie::SE3 T_a_b(motion.T_a_b.rotation(), motion.T_a_b.translation() * span_s);
  const lie::Vec3 rho = lie::se3::log(T_a_b).head<3>();
  return rho.normalized();
}

double travelAngleDeg(const InitResult& a, const InitResult& b) {
  const double c = std::clamp(startTravelDirection(a).dot(startTravelDirection(b)), -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

namespace {

/// A feature sampled at the knots: its bearing at the first knot it is defined at (the anchor), and its
/// normalized image points at later knots.
struct KnotTrack {
  int anchor = 0;
  lie::Vec3 f_anchor;
  std::vector<std::pair<int, Eigen::Vector2d>> seen;  ///< (knot index, normalized point)
};

std::vector<KnotTrack> sampleAtKnots(const TrackMap& tracks, const std::vector<int64_t>& times) {
  std::vector<KnotTrack> out;
  for (const auto& [id, track] : tracks) {
    KnotTrack k;
    k.anchor = -1;
    for (int i = 0; i < static_cast<int>(times.size()); ++i) {
      const auto p = track.pointAt(times[i]);
      if (!p) continue;
      if (k.anchor < 0) {
        k.anchor = i;
        k.f_anchor = view_geometry::ray(p->x(), p->y());
      } else {
        k.seen.emplace_back(i, *p);
      }
    }
    if (!k.seen.empty()) out.push_back(std::move(k));
  }
  return out;
}

/// The point along the anchor ray closest to the other rays (midpoint of each pair of rays, averaged
/// over the pairs that put it in front), as an inverse depth; 0 (a point at infinity) when no pair does.
double initialInverseDepth(const KnotTrack& k, const std::vector<lie::SE3>& poses) {
  const lie::Vec3 d_a = poses[k.anchor].rotation() * k.f_anchor;
  const lie::Vec3 p_a = poses[k.anchor].translation();
  double sum = 0;
  int n = 0;
  for (const auto& [i, xn] : k.seen) {
    const lie::Vec3 d_b = poses[i].rotation() * view_geometry::ray(xn.x(), xn.y());
    const lie::Vec3 w = p_a - poses[i].translation();
    const double b = d_a.dot(d_b), det = 1.0 - b * b;
    if (det < 1e-12) continue;
    const double lambda = (b * d_b.dot(w) - d_a.dot(w)) / det;  // closest point of the anchor ray
    if (lambda > 0 && std::isfinite(lambda)) {
      sum += lambda;
      ++n;
    }
  }
  return n > 0 ? n / sum : 0.0;
}

/// Whitened reprojection error of a feature seen at knot k, anchored at knot a, the knots' positions
/// held: the point in knot k's frame, scaled by the inverse depth ρ ≥ 0, is R_kᵀ (R_a f_a + ρ (p_a − p_k)),
/// so a point at infinity (ρ = 0) constrains the rotations only.
struct StartReprojection {
  StartReprojection(const lie::Vec3& f_a, const Eigen::Vector2d& xn, const lie::Vec3& baseline, double sigma)
      : f_a(f_a), xn(xn), baseline(baseline), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* q_a, const T* q_k, const T* rho, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Qa(q_a), Qk(q_k);
    const Eigen::Matrix<T, 3, 1> q = Qk.conjugate() * (Qa * f_a.cast<T>() + rho[0] * baseline.cast<T>());
    if (q.z() <= T(1e-9)) {  // behind the camera: a large, bounded residual
      r[0] = r[1] = T(10.0);
      return true;
    }
    r[0] = (q.x() / q.z() - xn.x()) / sigma;
    r[1] = (q.y() / q.z() - xn.y()) / sigma;
    return true;
  }
  lie::Vec3 f_a;
  Eigen::Vector2d xn;
  lie::Vec3 baseline;  ///< p_a − p_k
  double sigma;
};

/// Whitened change of the relative rotation between neighbour knot intervals (twice the vector part of
/// the relative quaternion, the rotation angle for small angles): an angular-acceleration prior.
struct RotationSmoothness {
  explicit RotationSmoothness(double sigma) : sigma(sigma) {}
  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q0(q0), Q1(q1), Q2(q2);
    Eigen::Quaternion<T> d01 = Q0.conjugate() * Q1, d12 = Q1.conjugate() * Q2;
    if (d01.w() < T(0)) d01.coeffs() = -d01.coeffs();
    if (d12.w() < T(0)) d12.coeffs() = -d12.coeffs();
    for (int i = 0; i < 3; ++i) r[i] = T(2) * (d12.vec()[i] - d01.vec()[i]) / sigma;
    return true;
  }
  double sigma;
};

}  // namespace

RotationRefinement refineStartRotations(Trajectory& trajectory, const TrackMap& tracks, double c) {
  RotationRefinement result;
  std::vector<Knot*> knots;
  std::vector<int64_t> times;
  std::vector<lie::SE3> before;
  for (auto& [t, knot] : trajectory.knots()) {
    knots.push_back(&knot);
    times.push_back(t);
    before.push_back(knot.T_w_c());
  }
  const int n_knots = static_cast<int>(knots.size());
  if (n_knots < 3) return result;
  result.intervals = n_knots - 1;
  const std::vector<KnotTrack> features = sampleAtKnots(tracks, times);
  std::vector<int> seen_at(n_knots, 0);
  for (const KnotTrack& k : features) {
    for (const auto& [i, xn] : k.seen) ++seen_at[i];
  }
  int fitted = 0;
  for (int i = 1; i < n_knots; ++i) fitted += seen_at[i] >= kMinRefitFeatures;
  if (fitted == 0) return result;
  // Parameters: each knot's rotation (unit quaternion, x y z w), the first one held (gauge), and every
  // feature's inverse depth along its anchor bearing, ≥ 0. Positions are held: over one knot interval a
  // rotation and a sideways step move the image alike, and only the start's baseline separates them.
  std::vector<Eigen::Vector4d> q(n_knots);
  for (int i = 0; i < n_knots; ++i) q[i] = Eigen::Quaterniond(before[i].rotation()).normalized().coeffs();
  std::vector<double> rho(features.size());
  for (std::size_t j = 0; j < features.size(); ++j) rho[j] = initialInverseDepth(features[j], before);

  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion;
  ceres::CauchyLoss cauchy(1.0);
  for (int i = 0; i < n_knots; ++i) problem.AddParameterBlock(q[i].data(), 4, &quaternion);
  problem.SetParameterBlockConstant(q[0].data());
  for (std::size_t j = 0; j < features.size(); ++j) {
    const KnotTrack& k = features[j];
    for (const auto& [i, xn] : k.seen) {
      const lie::Vec3 baseline = before[k.anchor].translation() - before[i].translation();
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<StartReprojection, 2, 4, 4, 1>(
                                   new StartReprojection(k.f_anchor, xn, baseline, c)),
                               &cauchy, q[k.anchor].data(), q[i].data(), &rho[j]);
    }
    problem.SetParameterLowerBound(&rho[j], 0, 0.0);
  }
  // Prior: the rotation is smooth on the knot grid, an angular acceleration of 20 rad/s² is one sigma
  // (it holds the rotation of a knot that few features see).
  const double dt = durationSeconds(times[0], times[1]);
  for (int i = 1; i + 1 < n_knots; ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RotationSmoothness, 3, 4, 4, 4>(
                                 new RotationSmoothness(20.0 * dt * dt)),
                             nullptr, q[i - 1].data(), q[i].data(), q[i + 1].data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = 20;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return result;
  std::vector<lie::SE3> after;
  for (int i = 0; i < n_knots; ++i) {
    const Eigen::Quaterniond Q(q[i](3), q[i](0), q[i](1), q[i](2));
    if (!Q.coeffs().allFinite()) return result;
    after.emplace_back(Q.normalized().toRotationMatrix(), before[i].translation());
  }
  result.refined = fitted;
  for (int i = 0; i < n_knots; ++i) {
    const double change = lie::so3::log(before[i].rotation().transpose() * after[i].rotation()).norm();
    result.max_change_deg = std::max(result.max_change_deg, change * 180.0 / M_PI);
  }
  // Velocities: the twist from each knot to the next (the last knot keeps its predecessor's).
  for (int k = 0; k < n_knots; ++k) {
    const int a = std::min(k, n_knots - 2);
    const double interval = durationSeconds(times[a], times[a + 1]);
    knots[k]->set(after[k], lie::se3::log(after[a].inverse() * after[a + 1]) / interval);
  }
  return result;
}

}  // namespace asynevo::backend
