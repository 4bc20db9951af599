// The frame-based baseline's KLT tracker (frames/klt_tracker.hpp) on a synthetic translating image.
#include "asynevo/frames/klt_tracker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace asynevo::frames {
namespace {

constexpr int kSuper = 4;  // the scene is drawn at 4x and views are area-averaged: exact quarter-pixel shifts

/// A smooth random texture (blurred uniform noise, fixed seed) at kSuper times the frame resolution,
/// larger than the frame so shifted views stay inside it.
cv::Mat texture() {
  cv::Mat noise(kSuper * 260, kSuper * 320, CV_32F);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0 * kSuper);
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  return noise;
}

/// The 240x180 view of `image` whose top-left corner is at (40 + dx, 40 + dy) frame pixels (dx, dy
/// multiples of 1/kSuper), area-averaged to 8 bits.
cv::Mat view(const cv::Mat& image, double dx, double dy) {
  const cv::Rect crop(static_cast<int>(kSuper * (40 + dx)), static_cast<int>(kSuper * (40 + dy)),
                      kSuper * 240, kSuper * 180);
  cv::Mat small, out;
  cv::resize(image(crop), small, cv::Size(240, 180), 0, 0, cv::INTER_AREA);
  small.convertTo(out, CV_8U);
  return out;
}

TEST(KltTracker, RecoversASubPixelShiftAndKeepsIds) {
  const CameraModel camera = CameraModel::pinhole(240, 180, 200, 200, 120, 90);
  KltTracker tracker(camera);
  const cv::Mat image = texture();
  const KltFrameResult first = tracker.track(0, view(image, 0, 0));
  ASSERT_GE(first.measurements.size(), 100u);
  EXPECT_TRUE(first.ended.empty());
  // The camera pans right: the scene moves left in the image by 3.25 px and up by 1.5 px.
  const KltFrameResult second = tracker.track(33'333'333, view(image, 3.25, 1.5));
  std::map<int64_t, TrackMeasurement> before;
  for (const TrackMeasurement& m : first.measurements) before[m.feature_id] = m;
  int matched = 0;
  std::vector<double> errors;
  for (const TrackMeasurement& m : second.measurements) {
    EXPECT_EQ(m.t_ns, 33'333'333);
    EXPECT_NEAR(m.xn, (m.x - 120) / 200, 1e-6);  // pinhole: normalized = (pixel - c) / f
    const auto it = before.find(m.feature_id);
    if (it == before.end()) continue;
    ++matched;
    errors.push_back(std::hypot(m.x - it->second.x + 3.25, m.y - it->second.y + 1.5));
  }
  std::sort(errors.begin(), errors.end());
  ASSERT_FALSE(errors.empty());
  // Lucas–Kanade is sub-pixel exact on most features; a few near the border (window partly outside)
  // or on weak texture are off by up to a few tenths.
  EXPECT_LT(errors[errors.size() / 2], 0.02);         // median
  EXPECT_LT(errors[errors.size() * 95 / 100], 0.15);  // 95th percentile
  EXPECT_LT(errors.back(), 0.5);
  EXPECT_GE(matched, 90);  // most survive: only those pushed out at the border end
  EXPECT_EQ(second.ended.size() + static_cast<std::size_t>(matched), first.measurements.size());
}

/// A grating of dark blocks, period 16 px in x and y (half-period blocks), at kSuper times the frame
/// resolution and wide enough for 80 px of motion.
cv::Mat grating() {
  cv::Mat image(kSuper * 260, kSuper * 420, CV_32F);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      image.at<float>(y, x) = (x / kSuper) % 16 < 8 && (y / kSuper) % 16 < 8 ? 70.f : 180.f;
  return image;
}

/// Median x displacement of the features seen in both results.
double medianDx(const KltFrameResult& a, const KltFrameResult& b) {
  std::map<int64_t, float> x;
  for (const TrackMeasurement& m : a.measurements) x[m.feature_id] = m.x;
  std::vector<double> dx;
  for (const TrackMeasurement& m : b.measurements)
    if (x.count(m.feature_id)) dx.push_back(m.x - x[m.feature_id]);
  if (dx.empty()) return 0;
  std::nth_element(dx.begin(), dx.begin() + static_cast<std::ptrdiff_t>(dx.size() / 2), dx.end());
  return dx[dx.size() / 2];
}

// The grating moves left faster and faster: 3, 5, ..., 13 px per frame (period 16 px). From one frame
// to the next, Lucas–Kanade finds the nearest match: beyond half a period that is the alias (the true
// motion minus 16 px). Started at a constant-velocity prediction it follows the true motion.
TEST(KltTracker, AliasesOnARepeatedTextureUnlessItPredicts) {
  const CameraModel camera = CameraModel::pinhole(240, 180, 200, 200, 120, 90);
  const cv::Mat image = grating();
  for (const bool predict : {false, true}) {
    KltOptions options;
    options.pyramid_levels = 1;
    options.predict = predict;
    KltTracker tracker(camera, options);
    double position = 0;
    KltFrameResult previous = tracker.track(0, view(image, position, 0));
    for (int step = 3; step <= 13; step += 2) {  // never exactly half a period
      position += step;
      const KltFrameResult next = tracker.track(step, view(image, position, 0));
      const double dx = medianDx(previous, next);
      const double expected = predict || step < 8 ? -step : 16 - step;
      EXPECT_NEAR(dx, expected, 0.05) << "predict " << predict << ", " << step << " px per frame";
      previous = next;
    }
  }
}

}  // namespace
}  // namespace asynevo::frames
