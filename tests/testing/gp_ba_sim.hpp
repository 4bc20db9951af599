#pragma once
// A small simulated GP bundle-adjustment problem, shared by the backend tests and benchmarks:
// a smooth (not exactly WNOA) camera trajectory, knots every knot_dt, world landmarks seen by tracks
// that span part of the window, noise-free normalized measurements at random times (reference/
// backend.md §5.7 and §6: 20 knots at 50 ms, 300 landmarks, 3000 measurements).

#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "asynevo/backend/factors/gp_projection_factor.hpp"
#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/backend/factors/se3_manifold.hpp"
#include "asynevo/backend/factors/wnoa_prior_factor.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::testing {

struct GpBaConfig {
  int knots = 20;
  int64_t knot_dt_ns = 50'000'000;
  int landmarks = 300;
  int measurements_per_landmark = 10;
  double track_fraction_min = 0.3;  // a track spans this fraction of the window ...
  double track_fraction_max = 0.7;  // ... up to this one
  double sigma = 1.0 / 200.0;       // normalized units (1 px at f = 200 px)
  double q_c = 1.0;                 // Q_c = q_c·I₆
  uint32_t seed = 7;
};

struct GpBaMeasurement {
  int landmark;
  int knot;  // t ∈ [t_knot, t_{knot+1}]
  int64_t t_ns;
  Eigen::Vector2d z;
};

/// Ground truth and measurements.
struct GpBaScenario {
  GpBaConfig config;
  std::vector<int64_t> knot_times_ns;
  std::vector<lie::SE3> poses;
  std::vector<lie::Vec6> velocities;
  std::vector<Eigen::Vector3d> landmarks;
  std::vector<GpBaMeasurement> measurements;

  /// Smooth truth: camera moving sideways and forward while rotating, looking along +z.
  static lie::SE3 truePose(double t) {
    const Eigen::Vector3d p(0.4 * std::sin(1.3 * t), 0.25 * std::cos(0.9 * t) - 0.25,
                            0.3 * t + 0.1 * std::sin(2.0 * t));
    const Eigen::Vector3d phi(0.15 * std::sin(1.1 * t), 0.25 * std::sin(0.7 * t + 0.3), 0.4 * t);
    return lie::SE3(lie::so3::exp(phi), p);
  }
  /// Body twist ϖ = (T⁻¹Ṫ)^∨ by a central difference of the smooth truth (error O(h²) ≈ 1e-10).
  static lie::Vec6 trueVelocity(double t) {
    const double h = 1e-5;
    return lie::se3::log(truePose(t - h).inverse() * truePose(t + h)) / (2.0 * h);
  }
};

inline GpBaScenario makeGpBaScenario(const GpBaConfig& config) {
  GpBaScenario s;
  s.config = config;
  std::mt19937 rng(config.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < config.knots; ++k) {
    const int64_t t = k * config.knot_dt_ns;
    s.knot_times_ns.push_back(t);
    s.poses.push_back(GpBaScenario::truePose(nsToSeconds(t)));
    s.velocities.push_back(GpBaScenario::trueVelocity(nsToSeconds(t)));
  }
  const int64_t t_end = s.knot_times_ns.back();
  while (static_cast<int>(s.landmarks.size()) < config.landmarks) {
    // Track span [t0, t1] inside the window; the landmark sits in front of the camera at its middle.
    const double fraction =
        config.track_fraction_min + (config.track_fraction_max - config.track_fraction_min) * uniform(rng);
    const int64_t span = static_cast<int64_t>(fraction * static_cast<double>(t_end));
    const int64_t t0 = static_cast<int64_t>(uniform(rng) * static_cast<double>(t_end - span));
    const int64_t t1 = t0 + span;
    const lie::SE3 T_mid = GpBaScenario::truePose(nsToSeconds((t0 + t1) / 2));
    const Eigen::Vector3d ray(uniform(rng) * 1.2 - 0.6, uniform(rng) * 0.9 - 0.45, 1.0);
    const Eigen::Vector3d p_w = T_mid * (ray * (2.0 + 4.0 * uniform(rng)));
    std::vector<GpBaMeasurement> track;
    for (int i = 0; i < config.measurements_per_landmark; ++i) {
      const int64_t t = t0 + static_cast<int64_t>(uniform(rng) * static_cast<double>(span));
      const lie::SE3 T = GpBaScenario::truePose(nsToSeconds(t));
      const Eigen::Vector3d p_c = T.inverse() * p_w;
      if (p_c.z() < 0.5 || std::abs(p_c.x() / p_c.z()) > 1.0 || std::abs(p_c.y() / p_c.z()) > 0.8) break;
      const int knot = std::min(static_cast<int>(t / config.knot_dt_ns), config.knots - 2);
      track.push_back({static_cast<int>(s.landmarks.size()), knot, t, p_c.head<2>() / p_c.z()});
    }
    if (static_cast<int>(track.size()) < config.measurements_per_landmark) continue;  // left the view
    s.landmarks.push_back(p_w);
    s.measurements.insert(s.measurements.end(), track.begin(), track.end());
  }
  return s;
}

/// Estimation state in Ceres parameter-block layout (pose_block.hpp).
struct GpBaState {
  std::vector<std::array<double, 7>> poses;
  std::vector<std::array<double, 6>> velocities;
  std::vector<std::array<double, 3>> landmarks;
};

inline GpBaState stateFromTruth(const GpBaScenario& s) {
  GpBaState x;
  for (size_t k = 0; k < s.poses.size(); ++k) {
    std::array<double, 7> pose{};
    backend::poseToBlock(s.poses[k], pose.data());
    x.poses.push_back(pose);
    std::array<double, 6> v{};
    Eigen::Map<lie::Vec6>(v.data()) = s.velocities[k];
    x.velocities.push_back(v);
  }
  for (const Eigen::Vector3d& p : s.landmarks) x.landmarks.push_back({p.x(), p.y(), p.z()});
  return x;
}

/// Truth perturbed: poses by Exp(δ) (σ_ρ = pose_sigma_m, σ_φ = pose_sigma_rad), velocities and
/// landmarks additively.
inline GpBaState perturbedState(const GpBaScenario& s, uint32_t seed, double pose_sigma_m = 0.02,
                                double pose_sigma_rad = 0.02, double vel_sigma = 0.05,
                                double landmark_sigma = 0.05) {
  GpBaState x = stateFromTruth(s);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (size_t k = 0; k < x.poses.size(); ++k) {
    lie::Vec6 d;
    d << pose_sigma_m * n(rng), pose_sigma_m * n(rng), pose_sigma_m * n(rng), pose_sigma_rad * n(rng),
        pose_sigma_rad * n(rng), pose_sigma_rad * n(rng);
    backend::poseToBlock(backend::poseFromBlock(x.poses[k].data()) * lie::se3::exp(d), x.poses[k].data());
    for (double& v : x.velocities[k]) v += vel_sigma * n(rng);
  }
  for (auto& p : x.landmarks) {
    for (double& c : p) c += landmark_sigma * n(rng);
  }
  return x;
}

/// Adds every factor of the scenario to `problem` over the blocks of `x` (which must outlive it).
/// `huber` > 0 wraps projections in a Huber loss with that threshold (whitened units).
inline void buildGpBaProblem(const GpBaScenario& s, GpBaState& x, ceres::Problem& problem,
                             double huber = 0.0) {
  const lie::Mat6 Q_c = s.config.q_c * lie::Mat6::Identity();
  for (size_t k = 0; k < x.poses.size(); ++k) {
    problem.AddParameterBlock(x.poses[k].data(), 7, new backend::SE3Manifold());
    problem.AddParameterBlock(x.velocities[k].data(), 6);
  }
  for (size_t k = 0; k + 1 < x.poses.size(); ++k) {
    problem.AddResidualBlock(new backend::WnoaPriorFactor(s.knot_times_ns[k], s.knot_times_ns[k + 1], Q_c),
                             nullptr, x.poses[k].data(), x.velocities[k].data(), x.poses[k + 1].data(),
                             x.velocities[k + 1].data());
  }
  for (const GpBaMeasurement& m : s.measurements) {
    const int k = m.knot;
    ceres::LossFunction* loss = huber > 0.0 ? new ceres::HuberLoss(huber) : nullptr;
    problem.AddResidualBlock(new backend::GpProjectionFactor(m.z, m.t_ns, s.knot_times_ns[k],
                                                             s.knot_times_ns[k + 1], s.config.sigma),
                             loss, x.poses[k].data(), x.velocities[k].data(), x.poses[k + 1].data(),
                             x.velocities[k + 1].data(), x.landmarks[m.landmark].data());
  }
}

/// RMSE of the knot positions against the truth (no alignment).
inline double positionRmse(const GpBaScenario& s, const GpBaState& x) {
  double sum = 0.0;
  for (size_t k = 0; k < s.poses.size(); ++k) {
    sum += (Eigen::Map<const Eigen::Vector3d>(x.poses[k].data()) - s.poses[k].translation()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(s.poses.size()));
}

}  // namespace asynevo::testing
