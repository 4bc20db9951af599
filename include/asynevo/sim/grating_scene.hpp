#pragma once
// The 'grating' scene of the repeated-texture experiment (docs/results/repeated_texture.md): a wall
// of identical dark blocks (sim::makeGratingTexture) facing the start pose, and a few distinct
// landmark panels (shapes texture) in front of it along the first metres of the start camera's x axis
// (for the start; the rest of the path sees only the repeated texture).
//
// Aliasing condition for a camera moving along x at speed v past the wall at depth Z, seen at frame
// rate F by a camera of focal length f (pixels): the texture moves f·v/(Z·F) pixels per frame and
// repeats every f·P/Z pixels, so the ratio is v/(F·P), independent of f and Z. At 9 m/s and 30 Hz the
// camera moves 0.30 m per frame, one period P = 0.29 m plus 3.4 %.

#include <cstdint>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/sim/motion.hpp"
#include "asynevo/sim/scene.hpp"

namespace asynevo::sim {

struct GratingGeometry {
  double wall_distance_m = 3.0;   ///< Z of the wall along the start optical axis
  double period_m = 0.29;         ///< texture period along x (and y)
  double panel_distance_m = 2.4;  ///< Z of the landmark panels
  double panel_size_m = 0.35;     ///< side of a landmark panel
  double panel_spacing_m = 2.5;   ///< panels every this many metres along x
  /// Panels only over the first this many metres of the path (the walking stretch of speed-ramp is
  /// 2.8 m): further on the camera sees the grating alone, a purely repeated texture.
  double panel_stretch_m = 4.0;
};

/// The grating scene for `motion` seen by `camera`.
Scene makeGratingScene(const Motion& motion, const CameraModel& camera, uint64_t seed,
                       const GratingGeometry& geometry = {});

}  // namespace asynevo::sim
