#pragma once
// Landmark rejoin (BackendConfig::landmark_rejoin_px): a new trajectory that starts where a landmark
// no longer measured still projects is that scene point seen again (the frontend re-detects a
// corner its tracker lost). Its measurements extend the landmark instead of founding a new one, so the
// point, and the scale it carries, stays in the window. The test is the one a fresh triangulation must
// pass (the largest reprojection error over the trajectory's views, docs/method/backend.md), applied
// to the existing point; it needs no parallax. Map-point association by projection is the usual
// remedy for short tracks in keyframe VO (ORB-SLAM's "search by projection", Mur-Artal et al., 2015).

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "asynevo/backend/feature_track.hpp"
#include "asynevo/backend/triangulation.hpp"

namespace asynevo::backend {

struct RejoinOptions {
  double max_error = 0;    ///< largest reprojection error over the views, normalized units
  double min_depth = 0.05; ///< smallest depth in any view
  /// Longest time from a landmark's last measurement to the new trajectory's first [ns]: a corner seen
  /// again soon is the same point; after longer, a junction of edges at different depths may not be.
  int64_t max_gap_ns = std::numeric_limits<int64_t>::max();
};

struct RejoinMatch {
  std::optional<int64_t> key;  ///< the landmark's trajectory key when exactly one candidate fits
  int candidates_fitting = 0;  ///< how many candidates passed the test (2 or more: ambiguous, none taken)
  /// With a key: the views' mean offset from the landmark's projection (normalized), which the new
  /// tracker's measurements carry (it sits on the corner a pixel or so from where the old one sat).
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};

/// The landmark a new trajectory rejoins: among `tracks`, the triangulated ones measured last before
/// `first_ns` (the new trajectory's first measurement; a landmark still measured since is another
/// point, the frontend keeps its features apart) and at most `max_gap_ns` before it, the one that
/// projects within `max_error` of every view and in front of every camera. None when no candidate, or
/// more than one, fits.
RejoinMatch findRejoinLandmark(const std::vector<TriangulationView>& views, int64_t first_ns, const TrackMap& tracks,
                               const RejoinOptions& options);

}  // namespace asynevo::backend
