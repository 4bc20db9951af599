#pragma once
// Feature trajectories as the backend keeps them: the measurements of one feature in time order and,
// once triangulated, its landmark (world xyz, a Ceres parameter block at a stable address).

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

struct Observation {
  int64_t t_ns = 0;
  Eigen::Vector2d xn = Eigen::Vector2d::Zero();  ///< normalized undistorted image point
};

/// A measurement whose knots left the window while its landmark stayed: the camera pose it was made
/// from is held fixed at its estimate (forced_marginalization: fixed_poses).
struct FixedView {
  lie::SE3 T_w_c;
  Eigen::Vector2d xn = Eigen::Vector2d::Zero();
};

struct FeatureTrack {
  int64_t id = 0;          ///< the key in TrackMap: the frontend's feature id, or a new id after a split
  std::vector<Observation> observations;  ///< time-ordered
  std::vector<FixedView> fixed_views;     ///< older measurements, from poses no longer in the window
  bool triangulated = false;
  /// No frontend feature extends it any more (its feature ended, or its tail was split off).
  bool feature_ended = false;
  std::array<double, 3> p_w{};            ///< landmark, valid when triangulated
  std::size_t observations_at_last_attempt = 0;

  int64_t firstTime() const { return observations.front().t_ns; }
  int64_t lastTime() const { return observations.back().t_ns; }
  /// Linear interpolation of the image point at t (inside [first, last]); nullopt outside.
  std::optional<Eigen::Vector2d> pointAt(int64_t t_ns) const;
  /// True when any observation lies in [from, to].
  bool observedIn(int64_t from_ns, int64_t to_ns) const;
  /// Removes observations with t < t_ns; returns how many.
  std::size_t dropBefore(int64_t t_ns);
};

/// Keyed by feature id: ordered, so iteration (and hence every decision) is deterministic.
using TrackMap = std::map<int64_t, FeatureTrack>;

}  // namespace asynevo::backend
