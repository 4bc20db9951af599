#pragma once
// What an initialization attempt found (docs/method/initialization.md): the motion over a span, or
// which check rejected it, with the counts.

#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

/// The check an attempt failed, in the order the checks are made: an attempt that tries several spans
/// or methods reports the furthest it got.
enum class InitRejection { None, Features, Motion, Model, Inliers, Parallax, Reversal, Agreement, Landmarks };
inline constexpr int kInitRejections = 9;

/// stats.json's name of a rejection: "features", "motion", "model", "inliers", "parallax", "reversal",
/// "agreement", "landmarks".
const char* rejectionName(InitRejection rejection);

/// One comparison of a motion with its depth-reversed alternative (init_depth_reversal,
/// docs/method/depth_reversal.md), as init_reversals.txt lists it.
struct ReversalCheck {
  int64_t t_a_ns = 0, t_b_ns = 0;
  const char* method = "two-view";
  int features = 0;
  double cost = 0;           ///< the motion's chirality cost
  double reversed_cost = 0;  ///< the alternative's (0 when none was found)
  bool found = false;        ///< an alternative was found
  lie::Vec3 t_b_a = lie::Vec3::Zero();           ///< the motion's translation direction over t_a .. t_b
  lie::Vec3 reversed_t_b_a = lie::Vec3::Zero();  ///< the alternative's
  /// a start: "kept", "reversed" or "tie" (the span waited); an audit: "kept", "against" or "restart"
  const char* decision = "kept";
  /// The audit's median parallax once the window's rotation is removed, in pixels (0 for a start's
  /// comparison).
  double parallax_px = 0;
};

struct InitResult {
  bool ok = false;
  const char* method = "two-view";  ///< "two-view" or "multi-view"
  std::string failure;              ///< when !ok: which check failed, with the counts
  InitRejection rejection = InitRejection::None;
  int64_t t_a_ns = 0;
  int64_t t_b_ns = 0;
  lie::SE3 T_a_b;          ///< camera at t_b in the frame of the camera at t_a, |t| = 1
  int features = 0;        ///< features that took part
  int inliers = 0;
  double parallax_px = 0;  ///< median inlier parallax (rotation removed), pixels
  /// A multi-view start chosen over a weak two-view start of the same attempt (init_weak_two_view).
  bool replaced_two_view = false;
  /// A two-view start built on the depth-reversed alternative of its five-point pose, which fitted
  /// better (init_depth_reversal).
  bool depth_reversed = false;
  /// Every comparison with a depth-reversed alternative the attempt made, whatever its outcome.
  std::vector<ReversalCheck> reversal_checks;
};

}  // namespace asynevo::backend
