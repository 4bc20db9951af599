#pragma once
// The frame-based baseline's frontend (ours, not DSO): sparse corners (OpenCV goodFeaturesToTrack, the
// Shi–Tomasi minimum-eigenvalue score: Shi & Tomasi, "Good features to track", CVPR 1994) tracked from
// frame to frame by pyramidal Lucas–Kanade (OpenCV calcOpticalFlowPyrLK: Bouguet, "Pyramidal
// implementation of the Lucas Kanade feature tracker", Intel 2000), with a forward–backward check
// (Kalal, Mikolajczyk & Matas, ICPR 2010). Each frame yields one TrackMeasurement per tracked feature
// at the frame's time, so the event pipeline's backend takes the tracks unchanged.

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/frontend/track_measurement.hpp"

namespace asynevo::frames {

struct KltOptions {
  int max_features = 150;         ///< features kept at once
  double quality_level = 0.01;    ///< goodFeaturesToTrack: relative corner score threshold
  double min_distance_px = 10.0;  ///< between features (new corners keep this from tracked ones)
  int window_px = 21;             ///< Lucas–Kanade window side
  int pyramid_levels = 3;         ///< pyramid levels above the image (OpenCV maxLevel)
  double max_fb_error_px = 1.0;   ///< forward–backward disagreement above which a track ends
  double border_px = 4.0;         ///< tracks closer than this to the image border end
  /// Start each Lucas–Kanade search at a constant-velocity prediction: the feature's displacement in
  /// the previous frame (a new feature: the median displacement of the others), instead of at its last
  /// position.
  bool predict = false;
};

/// What one frame produced: the measurements (in feature-id order) and the features that ended.
struct KltFrameResult {
  std::vector<TrackMeasurement> measurements;
  std::vector<int64_t> ended;
};

class KltTracker {
 public:
  /// `camera` undistorts the measured pixels (the measurement's xn, yn).
  KltTracker(const CameraModel& camera, const KltOptions& options = {});

  /// Tracks the features of the previous frame into `grey` (8-bit, the camera's size), ends the lost
  /// ones, tops the set up with new corners and returns a measurement of each at `t_ns`.
  KltFrameResult track(int64_t t_ns, const cv::Mat& grey);

  uint64_t featuresCreated() const { return next_id_; }
  std::size_t activeFeatures() const { return ids_.size(); }

 private:
  bool insideBorder(const cv::Point2f& p) const;

  CameraModel camera_;
  KltOptions options_;
  cv::Mat previous_;
  std::vector<cv::Point2f> points_;
  std::vector<int64_t> ids_;
  std::vector<cv::Point2f> displacements_;  ///< each feature's last displacement (zero when new)
  cv::Point2f median_displacement_{0, 0};   ///< of the features tracked into the previous frame
  int64_t next_id_ = 0;
};

}  // namespace asynevo::frames
