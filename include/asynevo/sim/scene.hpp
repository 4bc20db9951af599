#pragma once
// The simulated world: textured rectangles (planes) in 3D, seen against a uniform background.
//
// Built-in scenes (DESIGN.md §1): shapes, checkerboard, stripes, blobs (one large plane 1.5 m in front
// of the start pose, sized to cover everything the camera sees during the motion), poster (blobs with
// shapes, one plane), photo (one plane, a real photograph), sparse (one plane, few well separated
// polygons), boxes (textured cubes at 1–2 m before a background wall), room (the camera inside a
// textured box with at least 1.5 m clearance around the motion's bounding box) and photo-room (the
// same box with photographs on its walls), grating (a wall of blocks repeating every 0.29 m,
// sim/grating_scene.hpp). A scene file
// (YAML) lists planes explicitly: docs/simulator.md §Scene files.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/sim/motion.hpp"
#include "asynevo/sim/texture.hpp"

namespace asynevo::sim {

/// A textured rectangle. Its local frame has axes u, v in the plane and the normal n = u × v; the
/// texture's (0,0) corner sits at `texture_origin_m` in (u, v) coordinates relative to the centre.
struct TexturedPlane {
  std::string name;
  Eigen::Vector3d center_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_w = Eigen::Vector3d::UnitX();  ///< unit, first in-plane axis
  Eigen::Vector3d v_w = Eigen::Vector3d::UnitY();  ///< unit, second in-plane axis (⊥ u)
  double half_width = 1;                           ///< extent along u from the centre (m)
  double half_height = 1;                          ///< extent along v from the centre (m)
  std::shared_ptr<const Texture> texture;
  Eigen::Vector2d texture_origin_m = Eigen::Vector2d::Zero();
  float intensity_scale = 1.0f;  ///< multiplies the texture (e.g. to make walls darker)

  Eigen::Vector3d normal() const { return u_w.cross(v_w); }
};

struct Scene {
  std::string description;
  std::vector<TexturedPlane> planes;
  float background = 0.5f;  ///< intensity where no plane is hit
};

/// Names of the built-in scenes.
std::vector<std::string> sceneNames();

/// Where the photo scenes (photo, photo-room) find their photographs: Debian's python3-skimage data.
constexpr const char* kDefaultPhotoDirectory = "/usr/lib/python3/dist-packages/skimage/data";
/// The photo folder: $ASYNEVO_IMAGE_DIR when set and not empty, else kDefaultPhotoDirectory.
std::string photoDirectory();
/// photoDirectory()/file; throws InputError naming the file (and how to install it) when it is missing.
std::string photoPath(const std::string& file);
bool isBuiltinScene(const std::string& name);

/// Builds a built-in scene for `motion` seen by `camera`. Throws std::invalid_argument for an unknown
/// name.
Scene makeBuiltinScene(const std::string& name, const Motion& motion, const CameraModel& camera,
                       uint64_t seed);

/// Loads a scene file (YAML). Throws InputError (file and line) on bad content.
Scene loadSceneFile(const std::string& path, const Motion& motion, const CameraModel& camera, uint64_t seed);

/// A plane facing the camera at the motion's start: centred `distance` m along the start optical
/// axis, u = camera x, v = camera y, sized to cover every ray the camera casts onto it during the
/// motion (plus a margin, at most `max_half_size` m from the centre).
TexturedPlane planeInFrontOfStart(const Motion& motion, const CameraModel& camera, double distance,
                                  std::shared_ptr<const Texture> texture, double max_half_size = 25.0);

/// The six faces of a box centred at `center_w`, axes the columns of `R_w_b`, half extents
/// `half_extent` (m); face i gets textures[i % textures.size()].
std::vector<TexturedPlane> boxFaces(const std::string& name, const Eigen::Vector3d& center_w,
                                    const Eigen::Matrix3d& R_w_b, const Eigen::Vector3d& half_extent,
                                    const std::vector<std::shared_ptr<const Texture>>& textures);

}  // namespace asynevo::sim
