#pragma once
// What an initialization attempt found (docs/method/initialization.md): the motion over a span, or
// which check rejected it, with the counts.

#include <cstdint>
#include <string>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

/// The check an attempt failed, in the order the checks are made: an attempt that tries several spans
/// or methods reports the furthest it got.
enum class InitRejection { None, Features, Motion, Model, Inliers, Parallax, Agreement, Landmarks };
inline constexpr int kInitRejections = 8;

/// stats.json's name of a rejection: "features", "motion", "model", "inliers", "parallax", "agreement",
/// "landmarks".
const char* rejectionName(InitRejection rejection);

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
};

}  // namespace asynevo::backend
