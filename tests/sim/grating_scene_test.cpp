// The grating scene and texture of the repeated-texture experiment (sim/grating_scene.hpp).
#include "asynevo/sim/grating_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "asynevo/sim/texture.hpp"

namespace asynevo::sim {
namespace {

TEST(GratingTexture, RepeatsWithItsPeriodAndHasQuarterDarkBlocks) {
  TextureOptions options;
  options.tile_m = 4 * 0.29;
  const auto grating = makeGratingTexture(options, 0.29);
  int dark = 0, samples = 0;
  for (double u = 0.003; u < 0.29; u += 0.0071) {
    for (double v = 0.002; v < 0.29; v += 0.0073) {
      const float value = grating->sample(u, v, 0.001);
      ASSERT_NEAR(grating->sample(u + 0.29, v, 0.001), value, 1e-3);
      ASSERT_NEAR(grating->sample(u + 3 * 0.29, v + 0.58, 0.001), value, 1e-3);
      dark += value < 0.5f;
      ++samples;
    }
  }
  EXPECT_NEAR(static_cast<double>(dark) / samples, 0.25, 0.03);  // one half-by-half block per cell
  EXPECT_NEAR(grating->sample(0.05, 0.05, 0.001), 0.3, 1e-3);    // inside a block
  EXPECT_NEAR(grating->sample(0.20, 0.05, 0.001), 0.7, 1e-3);    // beside it
}

TEST(GratingScene, WallAtThreeMetresAndLandmarkPanelsAlongTheFirstMetres) {
  const auto motion = makePresetMotion("speed-ramp", 5.0);
  const Scene scene = makeBuiltinScene("grating", *motion, CameraModel::davis240cEcd(), 1);
  ASSERT_GE(scene.planes.size(), 2u);
  const TexturedPlane& wall = scene.planes.front();
  EXPECT_DOUBLE_EQ(wall.center_w.z(), 3.0);
  EXPECT_DOUBLE_EQ(wall.center_w.x(), 0.5 * 24.1);
  // The wall covers the 24.1 m the camera travels plus more than the view (~2.1 m) on either side.
  EXPECT_GT(wall.center_w.x() + wall.half_width, 24.1 + 3.0);
  EXPECT_LT(wall.center_w.x() - wall.half_width, -3.0);
  std::vector<double> panel_x;
  for (std::size_t i = 1; i < scene.planes.size(); ++i) {
    EXPECT_DOUBLE_EQ(scene.planes[i].center_w.z(), 2.4);
    panel_x.push_back(scene.planes[i].center_w.x());
  }
  // Every 2.5 m from before the start view to the first 4 m of the path plus its view (~1.5 m): -2.1, 0.4,
  // 2.9, 5.4; beyond, the camera sees the grating alone.
  ASSERT_EQ(panel_x.size(), 4u);
  EXPECT_NEAR(panel_x.front(), -2.1, 1e-9);
  EXPECT_NEAR(panel_x.back(), 5.4, 1e-9);
}

}  // namespace
}  // namespace asynevo::sim
