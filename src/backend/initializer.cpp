#include "asynevo/backend/initializer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>  // after Eigen (lie/se3.hpp, via initializer.hpp)
#include <string_view>
#include <vector>

#include "asynevo/backend/depth_reversal.hpp"
#include "asynevo/core/time.hpp"
#include "upper_median.hpp"
#include "view_geometry.hpp"

namespace asynevo::backend {

namespace {

struct Correspondences {
  std::vector<cv::Point2d> a, b;
  double median_px = 0;
};

Correspondences correspondences(const TrackMap& tracks, int64_t t_a, int64_t t_b, double focal) {
  Correspondences c;
  std::vector<double> displacement;
  for (const auto& [id, track] : tracks) {
    const auto pa = track.pointAt(t_a);
    const auto pb = track.pointAt(t_b);
    if (!pa || !pb) continue;
    c.a.emplace_back(pa->x(), pa->y());
    c.b.emplace_back(pb->x(), pb->y());
    displacement.push_back((*pb - *pa).norm() * focal);
  }
  if (!displacement.empty()) {
    c.median_px = upperMedian(displacement);
  }
  return c;
}

lie::Vec3 ray(const cv::Point2d& p) { return view_geometry::ray(p.x, p.y); }

/// Angle between the ray at t_b and the ray at t_a rotated into camera b: the parallax that the
/// translation alone causes (zero for a point at infinity).
double parallaxAngle(const lie::Mat3& R_b_a, const cv::Point2d& a, const cv::Point2d& b) {
  return view_geometry::angleBetween(R_b_a * ray(a), ray(b));
}

using view_geometry::Chirality;

struct PoseFromE {
  lie::Mat3 R_b_a;
  lie::Vec3 t_b_a;  ///< unit
  cv::Mat inliers;  ///< RANSAC inliers not seen behind a camera
  int count = 0;
};

/// The one of the four decompositions of E (Hartley & Zisserman, Multiple View Geometry, 2nd ed., §9.6.2)
/// that puts the most RANSAC inliers in front of both cameras. Unlike cv::recoverPose, a point far away
/// (parallax below `min_angle`) neither votes nor is discarded: with a short baseline most of a scene
/// can be more than 50 baselines away, and those points still pin the rotation.
PoseFromE poseFromEssential(const cv::Mat& E, const Correspondences& c, const cv::Mat& ransac_mask,
                            double min_angle) {
  cv::Mat R1, R2, t;
  cv::decomposeEssentialMat(E, R1, R2, t);
  lie::Vec3 t_unit;
  std::array<lie::Mat3, 2> rotations;
  cv::cv2eigen(t, t_unit);
  cv::cv2eigen(R1, rotations[0]);
  cv::cv2eigen(R2, rotations[1]);
  PoseFromE best;
  int best_front = -1;
  for (const lie::Mat3& R : rotations) {
    for (const double sign : {1.0, -1.0}) {
      const lie::Vec3 t_b_a = sign * t_unit;
      cv::Mat mask = cv::Mat::zeros(static_cast<int>(c.a.size()), 1, CV_8U);
      int front = 0, count = 0;
      for (std::size_t i = 0; i < c.a.size(); ++i) {
        if (ransac_mask.at<uchar>(static_cast<int>(i)) == 0) continue;
        const Chirality side = view_geometry::chirality(R, t_b_a, ray(c.a[i]), ray(c.b[i]), min_angle);
        if (side == Chirality::Behind) continue;
        front += side == Chirality::Front;
        mask.at<uchar>(static_cast<int>(i)) = 1;
        ++count;
      }
      if (front > best_front) {
        best_front = front;
        best = PoseFromE{R, t_b_a, mask, count};
      }
    }
  }
  return best;
}

/// The correspondences (bearings a, b) a motion explains: the Sampson distance of chiralResiduals within `ransac_px`, not
/// behind a camera (far points, below `min_angle` of parallax, count whatever their depth sign).
PoseFromE poseFromMotion(const TwoViewMotion& m, const std::vector<lie::Vec3>& a, const std::vector<lie::Vec3>& b,
                         double focal, double ransac_px, double min_angle) {
  const std::vector<double> r = chiralResiduals(m, a, b, focal);
  PoseFromE pose{m.R_b_a, m.t_b_a, cv::Mat::zeros(static_cast<int>(a.size()), 1, CV_8U), 0};
  for (std::size_t i = 0; i < a.size(); ++i) {
    // The Sampson distance, as the RANSAC of findEssentialMat measures it: 1/d² = 1/d_a² + 1/d_b².
    const double d_a = r[2 * i], d_b = r[2 * i + 1];
    if (d_a * d_a * d_b * d_b > ransac_px * ransac_px * (d_a * d_a + d_b * d_b)) continue;
    if (view_geometry::chirality(m.R_b_a, m.t_b_a, a[i], b[i], min_angle) == Chirality::Behind) continue;
    pose.inliers.at<uchar>(static_cast<int>(i)) = 1;
    ++pose.count;
  }
  return pose;
}

/// Median over `mask` of the parallax angle, in pixels (angle × focal).
double medianParallaxPx(const Correspondences& c, const lie::Mat3& R_b_a, const cv::Mat& mask, double focal) {
  std::vector<double> angles;
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    if (mask.at<uchar>(static_cast<int>(i)) != 0) angles.push_back(parallaxAngle(R_b_a, c.a[i], c.b[i]));
  }
  if (angles.empty()) return 0.0;
  return upperMedian(angles) * focal;
}

/// How well a span pins the baseline direction: its error shrinks with the parallax and with the square
/// root of the number of points.
double score(const InitResult& r) { return r.parallax_px * std::sqrt(static_cast<double>(r.inliers)); }

}  // namespace

const char* rejectionName(InitRejection rejection) {
  switch (rejection) {
    case InitRejection::None: return "none";
    case InitRejection::Features: return "features";
    case InitRejection::Motion: return "motion";
    case InitRejection::Model: return "model";
    case InitRejection::Inliers: return "inliers";
    case InitRejection::Parallax: return "parallax";
    case InitRejection::Reversal: return "reversal";
    case InitRejection::Agreement: return "agreement";
    case InitRejection::Landmarks: return "landmarks";
  }
  return "?";
}

InitResult initializeTwoViewSpan(const TrackMap& tracks, int64_t t_a, int64_t t_b, double focal,
                                    const BackendConfig& config) {
  InitResult r;
  r.t_a_ns = t_a;
  r.t_b_ns = t_b;
  const Correspondences c = correspondences(tracks, t_a, t_b, focal);
  const int n = static_cast<int>(c.a.size());
  r.features = n;
  const std::string span = fmt::format("{:.0f} ms", durationSeconds(t_a, t_b) * 1e3);
  if (n < config.init_min_features) {
    r.rejection = InitRejection::Features;
    r.failure = fmt::format("{}: {} features seen at both times (need {})", span, n, config.init_min_features);
    return r;
  }
  if (c.median_px < config.init_min_parallax_px) {
    r.rejection = InitRejection::Motion;
    r.failure = fmt::format("{}: median motion {:.1f} px (need {:.1f})", span, c.median_px, config.init_min_parallax_px);
    return r;
  }
  cv::Mat ransac_mask;
  // OpenCV's RANSAC draws from the calling thread's cv::theRNG(); seed it so that the same input always
  // gives the same pose (offline determinism, DESIGN.md §4 Threads).
  cv::theRNG().state = 0x5eed5eedULL + static_cast<uint64_t>(n);
  const cv::Mat E = cv::findEssentialMat(c.a, c.b, 1.0, cv::Point2d(0, 0), cv::RANSAC, 0.999,
                                         config.init_ransac_px / focal, ransac_mask);
  if (E.rows != 3 || E.cols != 3) {
    r.rejection = InitRejection::Model;
    r.failure = fmt::format("{}: no essential matrix from {} features", span, n);
    return r;
  }
  // Depth signs are trusted from twice the RANSAC threshold of parallax on.
  const double min_angle = 2.0 * config.init_ransac_px / focal;
  PoseFromE pose = poseFromEssential(E, c, ransac_mask, min_angle);
  if (pose.count < config.init_min_inliers) {
    r.rejection = InitRejection::Inliers;
    r.failure = fmt::format("{}: {} inliers not behind a camera (need {})", span, pose.count, config.init_min_inliers);
    return r;
  }
  // The depth-reversed alternative (init_depth_reversal): the translation reversed, the rotation turned
  // further, fitted to every correspondence; a clearly better fit is built on, and "wait" leaves a tie.
  if (config.init_depth_reversal != "off") {
    std::vector<lie::Vec3> a, b;
    for (std::size_t i = 0; i < c.a.size(); ++i) {
      a.push_back(ray(c.a[i]));
      b.push_back(ray(c.b[i]));
    }
    const auto reversal = findDepthReversal(TwoViewMotion{pose.R_b_a, pose.t_b_a}, a, b, focal, config.init_ransac_px);
    const std::string_view decision =
        decideReversal({t_a, t_b, r.method, n, reversal.given_cost, reversal.reversed_cost, reversal.reversed.has_value(),
                        pose.t_b_a, reversal.reversed ? reversal.reversed->t_b_a : lie::Vec3::Zero()},
                       span, config, &r);
    if (decision == "tie") return r;
    if (decision == "reversed") {
      pose = poseFromMotion(*reversal.reversed, a, b, focal, config.init_ransac_px, min_angle);
      r.depth_reversed = true;
      if (pose.count < config.init_min_inliers) {
        r.rejection = InitRejection::Inliers;
        r.failure = fmt::format("{}: {} inliers of the depth-reversed motion, which fits better (need {})", span,
                                pose.count, config.init_min_inliers);
        return r;
      }
    }
  }
  // Only translation makes parallax: a mostly rotating camera moves the image a lot but leaves the
  // baseline direction undetermined. Measure the motion that is left once the rotation is undone.
  const double parallax = medianParallaxPx(c, pose.R_b_a, pose.inliers, focal);
  if (parallax < config.init_min_parallax_px) {
    r.rejection = InitRejection::Parallax;
    r.failure = fmt::format("{}: median parallax {:.1f} px once the rotation ({:.1f} deg) is removed (need {:.1f})",
                            span, parallax, lie::so3::log(pose.R_b_a).norm() * 180.0 / M_PI,
                            config.init_min_parallax_px);
    return r;
  }
  // OpenCV: x_b = R x_a + t (points from camera a to camera b), i.e. T_b_a = [R | t].
  r.ok = true;
  r.T_a_b = lie::SE3(pose.R_b_a, pose.t_b_a).inverse();
  r.inliers = pose.count;
  r.parallax_px = parallax;
  return r;
}

InitResult initializeTwoView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                                const BackendConfig& config) {
  const int64_t window_ns = std::llround(config.init_window_ms * 1e6);
  InitResult best;
  best.t_b_ns = t_b_ns;
  std::string failures;
  std::vector<ReversalCheck> checks;
  int64_t previous_t_a = t_b_ns;
  for (int part = kInitSpans; part >= 1; --part) {
    const int64_t t_a = std::max(earliest_ns, t_b_ns - window_ns * part / kInitSpans);
    if (t_b_ns - t_a < window_ns / kInitSpans || t_a == previous_t_a) continue;
    previous_t_a = t_a;
    InitResult r = initializeTwoViewSpan(tracks, t_a, t_b_ns, focal, config);
    checks.insert(checks.end(), r.reversal_checks.begin(), r.reversal_checks.end());
    if (!r.ok) {
      failures += r.failure + "; ";
      best.rejection = std::max(best.rejection, r.rejection);
    } else if (!best.ok || score(r) > score(best)) {
      best = std::move(r);
    }
  }
  if (!best.ok) {
    best.failure = failures.empty() ? "not enough feature time span yet" : failures;
    if (failures.empty()) best.rejection = InitRejection::Features;
  }
  best.reversal_checks = std::move(checks);
  return best;
}

}  // namespace asynevo::backend
