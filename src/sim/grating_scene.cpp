#include "asynevo/sim/grating_scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace asynevo::sim {

Scene makeGratingScene(const Motion& motion, const CameraModel& camera, uint64_t seed,
                       const GratingGeometry& geometry) {
  Scene scene;
  TextureOptions wall_tex;
  wall_tex.seed = seed;
  // A tile of exactly 4 periods, so the period is not rounded.
  wall_tex.tile_m = 4 * geometry.period_m;
  TexturedPlane wall = planeInFrontOfStart(motion, camera, geometry.wall_distance_m,
                                           makeGratingTexture(wall_tex, geometry.period_m));
  wall.name = "grating wall";

  // The x range the motion covers (in the start frame). The wall spans it plus the widest view at the
  // wall on either side (planeInFrontOfStart caps planes at 25 m from the start, shorter than the path).
  const StampedPose start = motion.pose(motion.beginNs());
  const Eigen::Matrix3d R0 = start.q_w_c.toRotationMatrix();
  double x_lo = 0, x_hi = 0;
  for (int64_t t = motion.beginNs(); t <= motion.endNs(); t += 10'000'000) {
    const double x = R0.col(0).dot(motion.pose(t).p_w_c - start.p_w_c);
    x_lo = std::min(x_lo, x);
    x_hi = std::max(x_hi, x);
  }
  const double view_margin = geometry.wall_distance_m * camera.width() / camera.fx();  // 2x the half view
  wall.center_w = start.p_w_c + R0 * Eigen::Vector3d(0.5 * (x_lo + x_hi), 0, geometry.wall_distance_m);
  wall.half_width = std::max(wall.half_width, 0.5 * (x_hi - x_lo) + view_margin);
  scene.planes.push_back(wall);

  // Landmark panels over the first panel_stretch_m of that range (and the view before it).
  const double half_view = geometry.panel_distance_m * 0.5 * camera.width() / camera.fx();
  TextureOptions panel_tex;
  panel_tex.seed = seed + 7;
  panel_tex.tile_m = 0.5;
  panel_tex.texels = 512;
  const auto shapes = makeShapesTexture(panel_tex);
  int k = 0;
  for (double x = std::floor((x_lo - half_view) / geometry.panel_spacing_m) * geometry.panel_spacing_m + 0.4;
       x <= std::min(x_hi, x_lo + geometry.panel_stretch_m) + half_view; x += geometry.panel_spacing_m, ++k) {
    TexturedPlane panel;
    panel.name = fmt::format("landmark {}", k);
    const double y = (k % 2 == 0 ? -0.3 : 0.35);  // alternate above and below the optical axis
    panel.center_w = start.p_w_c + R0 * Eigen::Vector3d(x, y, geometry.panel_distance_m);
    panel.u_w = R0.col(0);
    panel.v_w = R0.col(1);
    panel.half_width = panel.half_height = geometry.panel_size_m / 2;
    panel.texture = shapes;
    panel.texture_origin_m = Eigen::Vector2d(0.13 * k, 0.29 * k);  // a different part of the tile each
    scene.planes.push_back(panel);
  }
  scene.description = fmt::format(
      "grating: a {:.1f} x {:.1f} m wall at {} m, {}, and {} landmark panels ({} m, shapes) at {} m every {} "
      "m",
      2 * wall.half_width, 2 * wall.half_height, geometry.wall_distance_m, wall.texture->description(), k,
      geometry.panel_size_m, geometry.panel_distance_m, geometry.panel_spacing_m);
  return scene;
}

}  // namespace asynevo::sim
