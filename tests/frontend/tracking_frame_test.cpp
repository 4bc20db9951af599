// The tracking frame (include/asynevo/frontend/tracking_frame.hpp): raw binned pixels, or the rectified
// pinhole image K_b undistort(pixel centre), with the sensor's border and the measurements mapped back
// through the camera model.
#include "asynevo/frontend/tracking_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace asynevo::frontend {
namespace {

// The matrix's DAVIS346 lens (equidistant, config/sensors/davis346.yaml) on a 640x480 sensor with a
// wider field of view, for binning 2.
CameraModel wideFisheye() {
  return CameraModel(640, 480, 420.0, 419.6, 322.4, 238.7, DistortionModel::kEquidistant,
                     {-0.048031442223833355, 0.011330957517194437, -0.055378166304281135, 0.021500973881459395});
}

TEST(TrackingFrame, TheRawFrameIsTheBinnedPixels) {
  const TrackingFrame frame(120, 90, 1, {});
  EXPECT_FALSE(frame.rectified());
  float x, y;
  ASSERT_TRUE(frame.position(7, 5, x, y));
  EXPECT_EQ(x, 7.f);
  EXPECT_EQ(y, 5.f);
  EXPECT_EQ(frame.originX(), 0.f);
  EXPECT_EQ(frame.gridWidth(), 120);
  EXPECT_EQ(frame.gridHeight(), 90);
  EXPECT_TRUE(frame.inside(16.f, 16.f, 16.f));
  EXPECT_FALSE(frame.inside(15.9f, 40.f, 16.f));
  EXPECT_FALSE(frame.inside(40.f, 89.f - 15.9f, 16.f));
  float u, v, xn, yn;
  ASSERT_TRUE(frame.measurement(10.f, 20.f, u, v, xn, yn));
  EXPECT_EQ(u, 20.5f);  // binned pixel centre (x + 0.5) 2 - 0.5
  EXPECT_EQ(v, 40.5f);
  EXPECT_EQ(xn, u);     // no table: identity
}

// Every pixel's position is the pinhole projection of its undistorted ray, and a measurement at that
// position gives the pixel back in sensor pixels (through the distortion) with the ray's coordinates.
void expectRoundTrip(const CameraModel& camera, int bin_shift) {
  const TrackingFrame frame(camera, bin_shift);
  ASSERT_TRUE(frame.rectified());
  EXPECT_EQ(frame.pixelsWithoutPosition(), 0);
  const int b = 1 << bin_shift;
  const int w = (camera.width() + b - 1) / b, h = (camera.height() + b - 1) / b;
  double worst_px = 0, worst_xn = 0;
  int outside_grid = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float fx, fy;
      ASSERT_TRUE(frame.position(x, y, fx, fy));
      const float gx = fx - frame.originX(), gy = fy - frame.originY();
      outside_grid += (gx >= 0.5f && gy >= 0.5f && gx < frame.gridWidth() - 1.5f && gy < frame.gridHeight() - 1.5f) ? 0 : 1;
      const Eigen::Vector2d pixel((x + 0.5) * b - 0.5, (y + 0.5) * b - 0.5);
      const Eigen::Vector2d ray = *camera.unproject(pixel);
      float u, v, xn, yn;
      ASSERT_TRUE(frame.measurement(fx, fy, u, v, xn, yn));
      worst_px = std::max(worst_px, std::hypot(u - pixel.x(), v - pixel.y()));
      worst_xn = std::max(worst_xn, std::hypot(xn - ray.x(), yn - ray.y()));
      // The border test is the binned sensor's, at the pixel itself.
      const float margin = 16.f;
      const bool inside_raw = x >= margin && y >= margin && x <= w - 1 - margin && y <= h - 1 - margin;
      if (std::abs(x - margin) > 0.01f && std::abs(y - margin) > 0.01f && std::abs(x - (w - 1 - margin)) > 0.01f &&
          std::abs(y - (h - 1 - margin)) > 0.01f) {
        EXPECT_EQ(frame.inside(fx, fy, margin), inside_raw) << x << " " << y;
      }
    }
  }
  EXPECT_EQ(outside_grid, 0);
  EXPECT_LT(worst_px, 2e-3);  // float positions, ~1e-5 of the frame's extent
  EXPECT_LT(worst_xn, 1e-5);
  // The frame is the pinhole image of the same intrinsics: the principal point keeps its place.
  float u, v, xn, yn;
  const float cx = static_cast<float>((camera.cx() + 0.5) / b - 0.5), cy = static_cast<float>((camera.cy() + 0.5) / b - 0.5);
  ASSERT_TRUE(frame.measurement(cx, cy, u, v, xn, yn));
  EXPECT_NEAR(u, camera.cx(), 1e-3);
  EXPECT_NEAR(xn, 0.0, 1e-6);
}

TEST(TrackingFrame, RectifiedPositionsRoundTripThroughTheCameraModel) {
  expectRoundTrip(CameraModel::davis240cEcd(), 0);
  expectRoundTrip(wideFisheye(), 1);
}

TEST(TrackingFrame, ABarrelLensStretchesTheFrameBeyondTheSensor) {
  // Barrel distortion: the corners' rays lie farther out than their pixels, so the rectified frame is
  // wider than the sensor, and a pixel step near the corner is longer than one there.
  const CameraModel camera = CameraModel::davis240cEcd();
  const TrackingFrame frame(camera, 0);
  float x0, y0, x1, y1, xc, yc, xc1, yc1;
  ASSERT_TRUE(frame.position(0, 0, x0, y0));
  ASSERT_TRUE(frame.position(1, 0, x1, y1));
  ASSERT_TRUE(frame.position(132, 110, xc, yc));
  ASSERT_TRUE(frame.position(133, 110, xc1, yc1));
  EXPECT_LT(x0, -1.f);
  EXPECT_LT(y0, -1.f);
  EXPECT_GT(frame.gridWidth(), camera.width());
  EXPECT_NEAR(xc1 - xc, 1.f, 0.01f);
  EXPECT_GT(x1 - x0, 1.2f);
}

}  // namespace
}  // namespace asynevo::frontend
