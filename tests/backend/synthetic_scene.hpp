#pragma once
// A synthetic world for estimator tests: a smooth 6-DoF camera trajectory in front of a cloud of
// landmarks, and perfect (or noisy) feature tracks of limited life, as the frontend would deliver them.

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "asynevo/frontend/track_measurement.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::testing {

struct SyntheticScene {
  double fx = 200, fy = 200, cx = 120, cy = 90;
  int width = 240, height = 180;
  std::vector<Eigen::Vector3d> landmarks;
  /// The camera motion measurements() sees; pose() unless a test sets another.
  std::function<lie::SE3(double)> trajectory = &SyntheticScene::pose;

  /// Ground-truth camera-to-world pose at time t (seconds): a gentle 6-DoF wobble while moving sideways.
  static lie::SE3 pose(double t) {
    const Eigen::Vector3d p(0.4 * std::sin(0.9 * t) + 0.1 * t, 0.2 * std::sin(1.3 * t + 0.5), 0.15 * std::sin(0.7 * t));
    const Eigen::Vector3d phi(0.08 * std::sin(1.1 * t), 0.12 * std::sin(0.8 * t + 0.3), 0.05 * std::sin(0.6 * t));
    return lie::SE3(lie::so3::exp(phi), p);
  }

  explicit SyntheticScene(int n_landmarks, unsigned seed = 3) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(-3.0, 3.5), uy(-2.0, 2.0), uz(2.5, 5.0);
    for (int i = 0; i < n_landmarks; ++i) landmarks.emplace_back(ux(rng), uy(rng), uz(rng));
  }

  /// Tracks: every landmark is re-detected as a new feature every `life_s`, with a measurement every
  /// `dt_s` while it stays in the image, plus Gaussian pixel noise.
  std::vector<TrackMeasurement> measurements(double duration_s, double dt_s, double life_s, double noise_px,
                                             unsigned seed = 5) const {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, noise_px);
    std::uniform_real_distribution<double> phase(0.0, life_s);
    std::vector<TrackMeasurement> out;
    int64_t next_id = 0;
    for (std::size_t j = 0; j < landmarks.size(); ++j) {
      double start = phase(rng);  // staggered feature births
      while (start < duration_s) {
        const int64_t id = next_id++;
        for (double t = start; t < std::min(start + life_s, duration_s); t += dt_s) {
          const Eigen::Vector3d p_c = trajectory(t).inverse() * landmarks[j];
          if (p_c.z() < 0.5) break;
          const double u = fx * p_c.x() / p_c.z() + cx + noise(rng), v = fy * p_c.y() / p_c.z() + cy + noise(rng);
          if (u < 5 || v < 5 || u > width - 6 || v > height - 6) break;
          TrackMeasurement m;
          m.feature_id = id;
          m.t_ns = std::llround(t * 1e9);
          m.x = static_cast<float>(u);
          m.y = static_cast<float>(v);
          m.xn = static_cast<float>((u - cx) / fx);
          m.yn = static_cast<float>((v - cy) / fy);
          out.push_back(m);
        }
        start += life_s;
      }
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
    return out;
  }
};

}  // namespace asynevo::testing
