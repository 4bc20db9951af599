#pragma once
// Ray casting of a Scene into a camera image: for each pixel, the ray through its centre (undistorted
// with the camera's lookup table, so distortion is exact) is intersected with every plane; the nearest
// hit is shaded with the mip-mapped texture at the pixel's footprint. Plane borders are anti-aliased by
// their analytic pixel coverage (the two nearest candidates are blended), so silhouettes do not jump
// from pixel to pixel.

#include <Eigen/Core>
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
  float shade(const Frame& frame, const Ray& ray) const;

  const CameraModel& camera_;
  const Scene& scene_;
  std::vector<Ray> rays_;
};

}  // namespace asynevo::sim
