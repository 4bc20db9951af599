#pragma once
// Feature tracks over one 500 ms initialization window, for the start's tests: points in front of a
// moving camera, each tracked for a limited life with staggered births, measured every 10 ms while in a
// 240×180 image (normalized coordinates, focal 200 px), with Gaussian noise.

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

constexpr double kFocal = 200.0;
constexpr int64_t kT0 = 1'000'000'000, kT1 = 1'500'000'000;  // a 500 ms window

using PoseAt = std::function<lie::SE3(double)>;  // camera-to-world at t seconds after kT0

/// Points 3–6 m in front of the camera, ±half_width_m sideways and ±0.75 half_width_m up; each is
/// tracked for `life_s` (staggered births). The track id changes at every rebirth.
inline TrackMap tracksOf(const PoseAt& pose, int n_points, double life_s, double noise_px, unsigned seed = 11,
                         double half_width_m = 2.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-half_width_m, half_width_m), uy(-0.75 * half_width_m, 0.75 * half_width_m),
      uz(3.0, 6.0), phase(0.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, noise_px / kFocal);
  TrackMap tracks;
  int64_t next_id = 0;
  for (int i = 0; i < n_points; ++i) {
    const Eigen::Vector3d p_w(ux(rng), uy(rng), uz(rng));
    for (double start = -phase(rng) * life_s; start < 0.5; start += life_s) {
      FeatureTrack track;
      track.id = next_id++;
      for (double t = std::max(0.0, start); t < std::min(start + life_s, 0.5 + 1e-9); t += 0.01) {
        const Eigen::Vector3d p_c = pose(t).inverse() * p_w;
        const Eigen::Vector2d xn(p_c.x() / p_c.z() + gaussian(rng), p_c.y() / p_c.z() + gaussian(rng));
        if (p_c.z() < 0.5 || std::abs(xn.x()) > 0.6 || std::abs(xn.y()) > 0.45) break;
        track.observations.push_back({kT0 + std::llround(t * 1e9), xn});
      }
      if (track.observations.size() >= 2) tracks[track.id] = std::move(track);
    }
  }
  return tracks;
}

/// A camera moving at the constant body twist (v, ω) from the identity.
inline PoseAt constantTwist(const Eigen::Vector3d& v, const Eigen::Vector3d& omega) {
  return [v, omega](double t) {
    lie::Vec6 xi;
    xi << v * t, omega * t;
    return lie::se3::exp(xi);
  };
}

}  // namespace asynevo::backend
