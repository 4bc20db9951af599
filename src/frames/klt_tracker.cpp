#include "asynevo/frames/klt_tracker.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

namespace asynevo::frames {

namespace {

/// Component-wise median.
cv::Point2f medianOf(const std::vector<cv::Point2f>& points) {
  std::vector<float> x, y;
  for (const cv::Point2f& p : points) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  const auto mid = static_cast<std::ptrdiff_t>(points.size() / 2);
  std::nth_element(x.begin(), x.begin() + mid, x.end());
  std::nth_element(y.begin(), y.begin() + mid, y.end());
  return {x[static_cast<std::size_t>(mid)], y[static_cast<std::size_t>(mid)]};
}

}  // namespace

KltTracker::KltTracker(const CameraModel& camera, const KltOptions& options)
    : camera_(camera), options_(options) {
  if (options_.max_features < 1 || options_.window_px < 3 || options_.pyramid_levels < 0)
    throw std::invalid_argument("KLT options: max_features >= 1, window_px >= 3, pyramid_levels >= 0");
}

bool KltTracker::insideBorder(const cv::Point2f& p) const {
  const double b = options_.border_px;
  return p.x >= b && p.y >= b && p.x <= camera_.width() - 1 - b && p.y <= camera_.height() - 1 - b;
}

KltFrameResult KltTracker::track(int64_t t_ns, const cv::Mat& grey) {
  if (grey.type() != CV_8UC1 || grey.cols != camera_.width() || grey.rows != camera_.height())
    throw std::invalid_argument("KltTracker: the frame must be 8-bit grey of the camera's size");
  KltFrameResult result;
  // 1. Track the previous frame's features, forward then backward.
  if (!points_.empty()) {
    const cv::Size window(options_.window_px, options_.window_px);
    const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
    std::vector<cv::Point2f> forward, backward;
    std::vector<uchar> status_f, status_b;
    std::vector<float> error;
    int flags = 0;
    if (options_.predict) {  // constant-velocity starts: forward at the prediction, backward at the start
      flags = cv::OPTFLOW_USE_INITIAL_FLOW;
      for (std::size_t i = 0; i < points_.size(); ++i) {
        const cv::Point2f d =
            displacements_[i] == cv::Point2f(0, 0) ? median_displacement_ : displacements_[i];
        forward.push_back(points_[i] + d);
      }
      backward = points_;
    }
    cv::calcOpticalFlowPyrLK(previous_, grey, points_, forward, status_f, error, window,
                             options_.pyramid_levels, criteria, flags);
    cv::calcOpticalFlowPyrLK(grey, previous_, forward, backward, status_b, error, window,
                             options_.pyramid_levels, criteria, flags);
    std::vector<cv::Point2f> kept_points, kept_displacements;
    std::vector<int64_t> kept_ids;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const cv::Point2f d = backward[i] - points_[i];
      const bool ok = status_f[i] && status_b[i] && insideBorder(forward[i]) &&
                      d.x * d.x + d.y * d.y <= options_.max_fb_error_px * options_.max_fb_error_px;
      if (ok) {
        kept_points.push_back(forward[i]);
        kept_displacements.push_back(forward[i] - points_[i]);
        kept_ids.push_back(ids_[i]);
      } else {
        result.ended.push_back(ids_[i]);
      }
    }
    if (!kept_displacements.empty()) median_displacement_ = medianOf(kept_displacements);
    points_ = std::move(kept_points);
    displacements_ = std::move(kept_displacements);
    ids_ = std::move(kept_ids);
  }
  // 2. New corners away from the tracked ones.
  const int wanted = options_.max_features - static_cast<int>(points_.size());
  if (wanted > 0) {
    cv::Mat mask(grey.size(), CV_8U, cv::Scalar(255));
    for (const cv::Point2f& p : points_)
      cv::circle(mask, p, static_cast<int>(options_.min_distance_px), cv::Scalar(0), cv::FILLED);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(grey, corners, wanted, options_.quality_level, options_.min_distance_px, mask);
    for (const cv::Point2f& c : corners) {
      if (!insideBorder(c)) continue;
      points_.push_back(c);
      displacements_.emplace_back(0.f, 0.f);
      ids_.push_back(next_id_++);
    }
  }
  // 3. One measurement per feature at the frame's time.
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const auto xn = camera_.unproject(Eigen::Vector2d(points_[i].x, points_[i].y));
    if (!xn) continue;
    TrackMeasurement m;
    m.feature_id = ids_[i];
    m.t_ns = t_ns;
    m.x = points_[i].x;
    m.y = points_[i].y;
    m.xn = static_cast<float>(xn->x());
    m.yn = static_cast<float>(xn->y());
    result.measurements.push_back(m);
  }
  previous_ = grey.clone();
  return result;
}

}  // namespace asynevo::frames
