#pragma once
// Ray casting of a Scene into a camera image: for each pixel, the ray through its centre (undistorted
// with the camera's lookup table, so distortion is exact) is intersected with every plane; the nearest
// hit is shaded with the mip-mapped texture at the pixel's footprint. Plane borders are anti-aliased by
// their analytic pixel coverage (the two nearest candidates are blended), so silhouettes do not jump
// from pixel to pixel.
//
// Speed: the image is split into 16x16-pixel tiles. For each tile and pose, a plane is kept only when the
// rays of the tile can hit its rectangle grown by half a pixel footprint (the anti-aliasing margin): the
// rays of a tile span a box in normalized coordinates, whose image on the plane is the convex hull of
// its corners' hits (a homography, as long as the plane's horizon n·r = 0 stays out of the box), and the
// footprint is bounded by |n·c| k_max / min (n·r)² over the corners. Culled planes are exactly those the
// per-pixel test would reject, and the kept ones are visited in the same order, so the image is the same
// bit for bit; only the work per pixel drops (from every plane to the few near the pixel).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/sim/scene.hpp"

namespace asynevo::sim {

class Renderer {
 public:
  /// Keeps references: `scene` must outlive the renderer.
  Renderer(const CameraModel& camera, const Scene& scene);

  /// Per-frame geometry of the planes in the camera frame; prepare once per pose, then render rows.
  struct Frame {
    struct Plane {
      Eigen::Vector3d n, u, v;  // normal and in-plane axes in the camera frame
      double dn = 0;            // n · (plane centre in camera frame): depth s = dn / (n · r)
      double au = 0, bv = 0;    // u · centre, v · centre
      double half_width = 0, half_height = 0;
      const TexturedPlane* source = nullptr;
    };
    std::vector<Plane> planes;
    // Per tile, the indices of the planes its pixels may see (ascending): tile t's are
    // tile_planes[tile_begin[t] .. tile_begin[t + 1]).
    std::vector<uint32_t> tile_begin;
    std::vector<uint16_t> tile_planes;
  };
  Frame prepare(const StampedPose& T_w_c) const;

  /// Linear intensity (texture units, [0, 1]) of rows [row_begin, row_end) into `image` (W*H, row-major).
  void render(const Frame& frame, float* image, int row_begin, int row_end) const;
  /// Whole image.
  std::vector<float> render(const StampedPose& T_w_c) const;

  /// Nearest-hit world points for a sparse grid of pixels (every `stride` pixels, borders included);
  /// pixels that see no plane are skipped. Used to bound the image motion between render steps.
  void sparseHits(const StampedPose& T_w_c, int stride, std::vector<Eigen::Vector2d>& pixels,
                  std::vector<Eigen::Vector3d>& points_w) const;

  const CameraModel& camera() const { return camera_; }

 private:
  struct Ray {
    double x = 0, y = 0;  // ray direction (x, y, 1) in the camera frame
    double k = 0;         // max(|∂r/∂px|, |∂r/∂py|) · |r|: footprint = depth · k / |n · r|
    bool valid = false;
  };
  /// The planes in the camera frame (no tile lists).
  Frame prepareGeometry(const StampedPose& T_w_c) const;
  float shade(const Frame& frame, const Ray& ray, const uint16_t* planes_begin, const uint16_t* planes_end) const;

  static constexpr int kTile = 16;
  struct Tile {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // box of the valid rays' normalized coordinates
    double k_max = 0;                       // largest ray.k of the tile
    bool any_valid = false;
  };

  const CameraModel& camera_;
  const Scene& scene_;
  std::vector<Ray> rays_;
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<Tile> tiles_;
};

}  // namespace asynevo::sim
