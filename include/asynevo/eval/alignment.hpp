#pragma once
// Trajectory alignment as rpg_trajectory_evaluation (align_utils.py / align_trajectory.py): find
// s, R, t with p_gt ≈ s R p_est + t.
//   sim3   Umeyama (1991) with scale, on the first N associated positions (all by default);
//   se3    Umeyama with s = 1; with N = 1 the first poses' full rigid transform;
//   posyaw rotation about z only (4-DoF), s = 1: with N = 1 from the first poses' orientations,
//          otherwise the yaw maximizing tr(Rz(θ)·C) of the Umeyama cross-covariance;
//   none   identity.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"

namespace asynevo::eval {

/// A problem with what is being evaluated (not with a file): too few poses, a degenerate
/// alignment, an invalid option.
class EvalError : public Error {
 public:
  using Error::Error;
};

enum class AlignType { kSim3, kSe3, kPosYaw, kNone };

/// "sim3", "se3", "posyaw", "none" (as rpg's align_type); nullopt for anything else.
std::optional<AlignType> parseAlignType(const std::string& text);
const char* alignTypeName(AlignType type);

/// p_gt ≈ scale * rotation * p_est + translation.
struct Similarity {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
};

/// Umeyama's closed form: minimizes Σ‖model_i − (s R data_i + t)‖². Both are 3×n with n ≥ 1
/// (n ≥ 2 for a meaningful scale). `with_scale` false fixes s = 1; `yaw_only` restricts R to a
/// rotation about z. Throws EvalError if the sizes differ or n = 0.
Similarity umeyama(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool with_scale,
                   bool yaw_only = false);

/// Aligns associated estimate poses to ground-truth poses (same length, index i ↔ i) with `type`,
/// using the first `num_frames` pairs (−1 = all). Throws EvalError for num_frames = 0, < −1, larger
/// than the number of pairs, or 1 with sim3.
Similarity alignTrajectory(const std::vector<Eigen::Vector3d>& p_est,
                           const std::vector<Eigen::Matrix3d>& R_est,
                           const std::vector<Eigen::Vector3d>& p_gt, const std::vector<Eigen::Matrix3d>& R_gt,
                           AlignType type, int num_frames = -1);

}  // namespace asynevo::eval
