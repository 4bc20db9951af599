#include "asynevo/backend/triangulation.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace asynevo::backend {

const char* triangulationFailureName(TriangulationFailure failure) {
  switch (failure) {
    case TriangulationFailure::kNone: return "none";
    case TriangulationFailure::kTooFewViews: return "too_few_views";
    case TriangulationFailure::kLowParallax: return "low_parallax";
    case TriangulationFailure::kDegenerate: return "degenerate";
    case TriangulationFailure::kBehindCamera: return "behind_camera";
    case TriangulationFailure::kHighError: return "high_error";
  }
  return "unknown";
}

namespace {

Eigen::Vector3d rayInWorld(const TriangulationView& v) {
  return (v.T_w_c.rotation() * Eigen::Vector3d(v.xn.x(), v.xn.y(), 1.0)).normalized();
}

}  // namespace

TriangulationResult triangulate(const std::vector<TriangulationView>& views, const TriangulationOptions& options) {
  TriangulationResult result;
  if (views.size() < 2) {
    result.failure = TriangulationFailure::kTooFewViews;
    return result;
  }
  const Eigen::Vector3d first_ray = rayInWorld(views.front());
  double max_cos_deficit = 0;
  for (const auto& v : views) max_cos_deficit = std::max(max_cos_deficit, 1.0 - first_ray.dot(rayInWorld(v)));
  result.parallax_deg = std::acos(std::clamp(1.0 - max_cos_deficit, -1.0, 1.0)) * 180.0 / M_PI;
  if (result.parallax_deg < options.min_parallax_deg) {
    result.failure = TriangulationFailure::kLowParallax;
    return result;
  }

  // Linear: each view gives x·(P3·X) − P1·X = 0 and y·(P3·X) − P2·X = 0 with P = [Rᵀ | −Rᵀt] (T_c_w).
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  for (const auto& v : views) {
    const lie::SE3 T_c_w = v.T_w_c.inverse();
    Eigen::Matrix<double, 3, 4> P;
    P << T_c_w.rotation(), T_c_w.translation();
    const Eigen::RowVector4d r1 = v.xn.x() * P.row(2) - P.row(0);
    const Eigen::RowVector4d r2 = v.xn.y() * P.row(2) - P.row(1);
    AtA += r1.transpose() * r1 + r2.transpose() * r2;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(AtA);
  const Eigen::Vector4d X = eigen.eigenvectors().col(0);
  if (std::abs(X.w()) < 1e-12 * X.head<3>().norm()) {
    result.failure = TriangulationFailure::kDegenerate;
    return result;
  }
  Eigen::Vector3d p_w = X.head<3>() / X.w();

  // Gauss-Newton on the normalized reprojection errors.
  for (int iteration = 0; iteration < options.refinement_iterations; ++iteration) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    bool ok = true;
    for (const auto& v : views) {
      const Eigen::Matrix3d Rt = v.T_w_c.rotation().transpose();
      const Eigen::Vector3d p_c = Rt * (p_w - v.T_w_c.translation());
      if (p_c.z() <= 1e-9) {
        ok = false;
        break;
      }
      const double iz = 1.0 / p_c.z();
      const Eigen::Vector2d r(p_c.x() * iz - v.xn.x(), p_c.y() * iz - v.xn.y());
      Eigen::Matrix<double, 2, 3> J_proj;
      J_proj << iz, 0, -p_c.x() * iz * iz, 0, iz, -p_c.y() * iz * iz;
      const Eigen::Matrix<double, 2, 3> J = J_proj * Rt;
      H += J.transpose() * J;
      g += J.transpose() * r;
    }
    if (!ok) break;
    const Eigen::Vector3d step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    p_w += step;
    if (step.norm() < 1e-10 * (1.0 + p_w.norm())) break;
  }

  double squared_sum = 0;
  for (const auto& v : views) {
    const Eigen::Vector3d p_c = v.T_w_c.inverse() * p_w;
    if (!(p_c.z() >= options.min_depth)) {
      result.failure = TriangulationFailure::kBehindCamera;
      return result;
    }
    const Eigen::Vector2d e = p_c.head<2>() / p_c.z() - v.xn;
    result.max_error = std::max(result.max_error, e.norm());
    squared_sum += e.squaredNorm();
  }
  result.rms_error = std::sqrt(squared_sum / static_cast<double>(views.size()));
  if (!((options.rms_error ? result.rms_error : result.max_error) <= options.max_error)) {
    result.failure = TriangulationFailure::kHighError;
    return result;
  }
  result.p_w = p_w;
  return result;
}

TriangulationViews triangulationViewsFromName(const std::string& name) {
  if (name == "all") return TriangulationViews::kAll;
  if (name == "solved") return TriangulationViews::kSolved;
  if (name == "solved_then_all") return TriangulationViews::kSolvedThenAll;
  throw std::invalid_argument("unknown triangulation_views '" + name + "'");
}

TriangulationResult triangulateTrajectory(const std::vector<TriangulationView>& views, std::size_t solved,
                                          TriangulationViews rule, std::size_t min_views,
                                          const TriangulationOptions& options) {
  const auto fromViews = [&](std::size_t n) {
    if (n < min_views) {
      TriangulationResult too_few;
      too_few.failure = TriangulationFailure::kTooFewViews;
      return too_few;
    }
    return n == views.size() ? triangulate(views, options)
                             : triangulate(std::vector<TriangulationView>(views.begin(), views.begin() + n), options);
  };
  solved = std::min(solved, views.size());
  if (rule == TriangulationViews::kAll || solved == views.size()) return fromViews(views.size());
  if (rule == TriangulationViews::kSolved) return fromViews(solved);
  TriangulationResult result = fromViews(solved);
  if (result.p_w || (result.failure != TriangulationFailure::kTooFewViews &&
                     result.failure != TriangulationFailure::kLowParallax))
    return result;
  return fromViews(views.size());
}

}  // namespace asynevo::backend
