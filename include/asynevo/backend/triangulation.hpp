#pragma once
// Multi-view triangulation of one feature trajectory from GP-interpolated camera poses: linear (DLT on
// the homogeneous point, smallest eigenvector of AᵀA) followed by a few Gauss-Newton steps on the
// normalized reprojection error (Hartley & Zisserman, Multiple View Geometry, §12.2). The result is
// checked for parallax, depth and reprojection error (the largest over the views, or their RMS), and a
// failure says which check failed.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

/// One observation: the camera pose at the measurement time and the normalized image point.
struct TriangulationView {
  lie::SE3 T_w_c;
  Eigen::Vector2d xn;
};

struct TriangulationOptions {
  double min_parallax_deg = 1.0;  ///< largest angle between any view's ray and the first view's ray
  double max_error = 3.0 / 200;   ///< largest reprojection error, normalized units (px / focal length)
  /// The reprojection test bounds the RMS error over the views instead of the largest one: one poor
  /// measurement among many then does not keep a trajectory from ever becoming a landmark.
  bool rms_error = false;
  double min_depth = 0.05;        ///< smallest depth in any view
  int refinement_iterations = 5;
};

enum class TriangulationFailure { kNone, kTooFewViews, kLowParallax, kDegenerate, kBehindCamera, kHighError };
constexpr int kTriangulationFailureCount = 6;
const char* triangulationFailureName(TriangulationFailure failure);

struct TriangulationResult {
  std::optional<Eigen::Vector3d> p_w;  ///< set when every check passed
  TriangulationFailure failure = TriangulationFailure::kNone;
  double parallax_deg = 0;
  double max_error = 0;  ///< normalized units
  double rms_error = 0;  ///< normalized units, over the views
};

TriangulationResult triangulate(const std::vector<TriangulationView>& views, const TriangulationOptions& options);

/// Which of a trajectory's views a new landmark of an open segment is triangulated from
/// (BackendConfig::triangulation_views). The window's newest knots, added since its latest solve, are a
/// constant-velocity prediction, and under acceleration their poses can be pixels off.
enum class TriangulationViews {
  kAll,            ///< every view in the window
  kSolved,         ///< the views up to the latest solve's newest knot only
  kSolvedThenAll,  ///< those, and every view where they are too few or hold too little parallax
};
/// "all", "solved" or "solved_then_all" (a validated config value); throws std::invalid_argument otherwise.
TriangulationViews triangulationViewsFromName(const std::string& name);

/// triangulate() by `rule`: `views` in time order, of which the first `solved` lie at or before the
/// latest solve's newest knot. Fewer than `min_views` views to triangulate from: kTooFewViews.
TriangulationResult triangulateTrajectory(const std::vector<TriangulationView>& views, std::size_t solved,
                                          TriangulationViews rule, std::size_t min_views,
                                          const TriangulationOptions& options);

}  // namespace asynevo::backend
