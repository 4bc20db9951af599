#include "asynevo/backend/initializer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <vector>

#include "asynevo/core/time.hpp"

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
    std::nth_element(displacement.begin(), displacement.begin() + displacement.size() / 2, displacement.end());
    c.median_px = displacement[displacement.size() / 2];
  }
  return c;
}

/// Median over the RANSAC inliers of the angle between the ray at t_b and the ray at t_a rotated into
/// camera b, in pixels (angle × focal): the image motion translation alone would cause.
double medianParallaxPx(const Correspondences& c, const lie::Mat3& R_b_a, const cv::Mat& inlier_mask,
                        double focal) {
  std::vector<double> angles;
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    if (!inlier_mask.empty() && inlier_mask.at<uchar>(static_cast<int>(i)) == 0) continue;
    const lie::Vec3 ray_a = R_b_a * lie::Vec3(c.a[i].x, c.a[i].y, 1.0).normalized();
    const lie::Vec3 ray_b = lie::Vec3(c.b[i].x, c.b[i].y, 1.0).normalized();
    angles.push_back(std::atan2(ray_a.cross(ray_b).norm(), ray_a.dot(ray_b)));
  }
  if (angles.empty()) return 0.0;
  std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
  return angles[angles.size() / 2] * focal;
}

}  // namespace

TwoViewResult initializeTwoView(const TrackMap& tracks, int64_t earliest_ns, int64_t t_b_ns, double focal,
                                const BackendConfig& config) {
  TwoViewResult result;
  result.t_b_ns = t_b_ns;
  const int64_t window_ns = std::llround(config.init_window_ms * 1e6);
  std::string failures;
  for (int part = 3; part >= 1; --part) {
    const int64_t t_a = std::max(earliest_ns, t_b_ns - window_ns * part / 3);
    if (t_b_ns - t_a < window_ns / 6) break;
    const Correspondences c = correspondences(tracks, t_a, t_b_ns, focal);
    const int n = static_cast<int>(c.a.size());
    const std::string span = fmt::format("{:.0f} ms", durationSeconds(t_a, t_b_ns) * 1e3);
    if (n < config.init_min_features) {
      failures += fmt::format("{}: {} features seen at both times (need {}); ", span, n, config.init_min_features);
      continue;
    }
    if (c.median_px < config.init_min_parallax_px) {
      failures += fmt::format("{}: median motion {:.1f} px (need {:.1f}); ", span, c.median_px,
                              config.init_min_parallax_px);
      continue;
    }
    cv::Mat inlier_mask;
    // OpenCV's RANSAC draws from the calling thread's cv::theRNG(); seed it so that the same input always
    // gives the same pose (offline determinism, DESIGN.md §4 Threads).
    cv::theRNG().state = 0x5eed5eedULL + static_cast<uint64_t>(n);
    const cv::Mat E = cv::findEssentialMat(c.a, c.b, 1.0, cv::Point2d(0, 0), cv::RANSAC, 0.999,
                                           config.init_ransac_px / focal, inlier_mask);
    if (E.rows != 3 || E.cols != 3) {
      failures += fmt::format("{}: no essential matrix from {} features; ", span, n);
      continue;
    }
    cv::Mat R, t;
    const int inliers = cv::recoverPose(E, c.a, c.b, R, t, 1.0, cv::Point2d(0, 0), inlier_mask);
    if (inliers < config.init_min_inliers) {
      failures += fmt::format("{}: {} inliers in front of both cameras (need {}); ", span, inliers,
                              config.init_min_inliers);
      continue;
    }
    // OpenCV: x_b = R x_a + t (points from camera a to camera b), i.e. T_b_a = [R | t].
    lie::Mat3 R_b_a;
    lie::Vec3 t_b_a;
    for (int i = 0; i < 3; ++i) {
      t_b_a(i) = t.at<double>(i);
      for (int j = 0; j < 3; ++j) R_b_a(i, j) = R.at<double>(i, j);
    }
    // Only translation makes parallax: a mostly rotating camera moves the image a lot but leaves the
    // baseline direction undetermined. Measure the motion that is left once the rotation is undone.
    const double parallax = medianParallaxPx(c, R_b_a, inlier_mask, focal);
    if (parallax < config.init_min_parallax_px) {
      failures += fmt::format("{}: median parallax {:.1f} px once the rotation ({:.1f} deg) is removed (need {:.1f}); ",
                              span, parallax, lie::so3::log(R_b_a).norm() * 180.0 / M_PI,
                              config.init_min_parallax_px);
      continue;
    }
    result.ok = true;
    result.t_a_ns = t_a;
    result.T_a_b = lie::SE3(R_b_a, t_b_a.normalized()).inverse();
    result.features = n;
    result.inliers = inliers;
    result.parallax_px = parallax;
    return result;
  }
  result.failure = failures.empty() ? "not enough feature time span yet" : failures;
  return result;
}

}  // namespace asynevo::backend
