#include "asynevo/eval/alignment.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

namespace asynevo::eval {

namespace {

Eigen::Matrix3d rotZ(double theta) {
  return Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// The yaw θ maximizing tr(Rz(θ)·C) (rpg: get_best_yaw).
double bestYaw(const Eigen::Matrix3d& C) {
  const double a = C(0, 1) - C(1, 0);
  const double b = C(0, 0) + C(1, 1);
  return M_PI / 2.0 - std::atan2(b, a);
}

Eigen::Matrix3Xd stack(const std::vector<Eigen::Vector3d>& points, std::size_t n) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) m.col(static_cast<Eigen::Index>(i)) = points[i];
  return m;
}

}  // namespace

std::optional<AlignType> parseAlignType(const std::string& text) {
  if (text == "sim3") return AlignType::kSim3;
  if (text == "se3") return AlignType::kSe3;
  if (text == "posyaw") return AlignType::kPosYaw;
  if (text == "none") return AlignType::kNone;
  return std::nullopt;
}

const char* alignTypeName(AlignType type) {
  switch (type) {
    case AlignType::kSim3:
      return "sim3";
    case AlignType::kSe3:
      return "se3";
    case AlignType::kPosYaw:
      return "posyaw";
    case AlignType::kNone:
      break;
  }
  return "none";
}

Similarity umeyama(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool with_scale,
                   bool yaw_only) {
  if (model.cols() != data.cols() || model.cols() == 0) {
    throw EvalError(fmt::format("alignment needs equally many points (got {} and {}), at least one",
                                model.cols(), data.cols()));
  }
  const double n = static_cast<double>(model.cols());
  const Eigen::Vector3d mu_m = model.rowwise().mean();
  const Eigen::Vector3d mu_d = data.rowwise().mean();
  const Eigen::Matrix3Xd m0 = model.colwise() - mu_m;
  const Eigen::Matrix3Xd d0 = data.colwise() - mu_d;
  const Eigen::Matrix3d C = m0 * d0.transpose() / n;  // correlation
  const double sigma2 = d0.squaredNorm() / n;         // variance of the data points

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (U.determinant() * V.determinant() < 0.0) S(2, 2) = -1.0;

  Similarity sim;
  if (yaw_only) {
    sim.rotation = rotZ(bestYaw(d0 * m0.transpose()));
  } else {
    sim.rotation = U * S * V.transpose();
  }
  if (with_scale) {
    if (!(sigma2 > 0.0)) throw EvalError("Sim(3) alignment: the estimate's positions are all equal");
    sim.scale = (svd.singularValues().asDiagonal() * S).trace() / sigma2;
  }
  sim.translation = mu_m - sim.scale * (sim.rotation * mu_d);
  return sim;
}

Similarity alignTrajectory(const std::vector<Eigen::Vector3d>& p_est,
                           const std::vector<Eigen::Matrix3d>& R_est,
                           const std::vector<Eigen::Vector3d>& p_gt, const std::vector<Eigen::Matrix3d>& R_gt,
                           AlignType type, int num_frames) {
  const std::size_t total = p_est.size();
  if (p_gt.size() != total || R_est.size() != total || R_gt.size() != total) {
    throw EvalError("alignment: estimate and ground truth have different numbers of poses");
  }
  if (type == AlignType::kNone) return Similarity{};
  if (num_frames == 0 || num_frames < -1) {
    throw EvalError(fmt::format("--align-frames must be -1 (all) or at least 1, not {}", num_frames));
  }
  if (num_frames > 0 && static_cast<std::size_t>(num_frames) > total) {
    throw EvalError(fmt::format("--align-frames {} exceeds the {} associated poses", num_frames, total));
  }
  const std::size_t n = num_frames < 0 ? total : static_cast<std::size_t>(num_frames);
  if (total == 0) throw EvalError("alignment: no poses");
  Similarity sim;
  switch (type) {
    case AlignType::kSim3:
      if (n < 2) throw EvalError("sim3 alignment needs at least 2 frames (--align-frames)");
      return umeyama(stack(p_gt, n), stack(p_est, n), /*with_scale=*/true);
    case AlignType::kSe3:
      if (n == 1) {  // the first poses' rigid transform
        sim.rotation = R_gt[0] * R_est[0].transpose();
        sim.translation = p_gt[0] - sim.rotation * p_est[0];
        return sim;
      }
      return umeyama(stack(p_gt, n), stack(p_est, n), /*with_scale=*/false);
    case AlignType::kPosYaw:
      if (n == 1) {  // yaw from the first orientations, translation from the first positions
        sim.rotation = rotZ(bestYaw(R_est[0] * R_gt[0].transpose()));
        sim.translation = p_gt[0] - sim.rotation * p_est[0];
        return sim;
      }
      return umeyama(stack(p_gt, n), stack(p_est, n), /*with_scale=*/false, /*yaw_only=*/true);
    case AlignType::kNone:
      break;
  }
  return sim;
}

}  // namespace asynevo::eval
