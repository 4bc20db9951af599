#include "asynevo/sim/scene.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/lie/so3.hpp"
#include "asynevo/sim/grating_scene.hpp"

namespace asynevo::sim {

namespace {

Eigen::Matrix3d rotationOf(const StampedPose& pose) { return pose.q_w_c.toRotationMatrix(); }

/// A few hundred poses spread over the motion (for sizing scenes).
StampedTrajectory coarseSamples(const Motion& motion) {
  const int64_t span = motion.endNs() - motion.beginNs();
  const int64_t dt = std::max<int64_t>(span / 400, 1'000'000);
  return sampleMotion(motion, dt);
}

/// Unit rays (camera frame) through pixels along the image border and a coarse inner grid.
std::vector<Eigen::Vector3d> borderRays(const CameraModel& camera) {
  std::vector<Eigen::Vector3d> rays;
  const int steps = 12;
  for (int i = 0; i <= steps; ++i) {
    for (int j = 0; j <= steps; ++j) {
      const double x = (camera.width() - 1) * static_cast<double>(i) / steps;
      const double y = (camera.height() - 1) * static_cast<double>(j) / steps;
      if (auto xn = camera.unproject(Eigen::Vector2d(x, y))) rays.emplace_back(xn->x(), xn->y(), 1.0);
    }
  }
  return rays;
}

}  // namespace

std::vector<std::string> sceneNames() {
  return {"shapes", "checkerboard", "stripes", "blobs", "poster", "boxes", "room", "photo", "photo-room", "sparse", "grating"};
}

std::string photoDirectory() {
  const char* env = std::getenv("ASYNEVO_IMAGE_DIR");
  return env && *env ? std::string(env) : std::string(kDefaultPhotoDirectory);
}

std::string photoPath(const std::string& file) {
  const std::filesystem::path path = std::filesystem::path(photoDirectory()) / file;
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path.string(),
                     "missing image for the photo scenes: install Debian's python3-skimage "
                     "(apt-get install python3-skimage) or set ASYNEVO_IMAGE_DIR to a folder that holds " +
                         file);
  }
  return path.string();
}

bool isBuiltinScene(const std::string& name) {
  const auto names = sceneNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

TexturedPlane planeInFrontOfStart(const Motion& motion, const CameraModel& camera, double distance,
                                  std::shared_ptr<const Texture> texture, double max_half_size) {
  const StampedPose start = motion.pose(motion.beginNs());
  const Eigen::Matrix3d R0 = rotationOf(start);
  TexturedPlane plane;
  plane.center_w = start.p_w_c + R0 * Eigen::Vector3d(0, 0, distance);
  plane.u_w = R0.col(0);
  plane.v_w = R0.col(1);
  const Eigen::Vector3d n = plane.normal();
  double half_u = 0.2 * distance, half_v = 0.2 * distance;
  const std::vector<Eigen::Vector3d> rays = borderRays(camera);
  for (const StampedPose& pose : coarseSamples(motion)) {
    const Eigen::Matrix3d R = rotationOf(pose);
    for (const Eigen::Vector3d& ray_c : rays) {
      const Eigen::Vector3d d = R * ray_c;
      const double denom = n.dot(d);
      if (std::fabs(denom) < 1e-9) continue;
      const double s = n.dot(plane.center_w - pose.p_w_c) / denom;
      if (!(s > 0)) continue;
      const Eigen::Vector3d q = pose.p_w_c + s * d - plane.center_w;
      half_u = std::max(half_u, std::fabs(q.dot(plane.u_w)));
      half_v = std::max(half_v, std::fabs(q.dot(plane.v_w)));
    }
  }
  plane.half_width = std::min(half_u * 1.1 + 0.05, max_half_size);
  plane.half_height = std::min(half_v * 1.1 + 0.05, max_half_size);
  if (texture && !texture->repeats()) {
    plane.texture_origin_m = Eigen::Vector2d(-texture->widthMeters() / 2, -texture->heightMeters() / 2);
  }
  plane.texture = std::move(texture);
  return plane;
}

std::vector<TexturedPlane> boxFaces(const std::string& name, const Eigen::Vector3d& center_w,
                                    const Eigen::Matrix3d& R_w_b, const Eigen::Vector3d& half_extent,
                                    const std::vector<std::shared_ptr<const Texture>>& textures) {
  std::vector<TexturedPlane> faces;
  const char* labels[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int sign : {1, -1}) {
      TexturedPlane face;
      face.name = fmt::format("{} {}", name, labels[2 * axis + (sign > 0 ? 0 : 1)]);
      face.center_w = center_w + sign * half_extent[axis] * R_w_b.col(axis);
      face.u_w = R_w_b.col(a1);
      face.v_w = sign * R_w_b.col(a2);
      face.half_width = half_extent[a1];
      face.half_height = half_extent[a2];
      face.texture = textures[faces.size() % textures.size()];
      face.texture_origin_m = Eigen::Vector2d(0.37 * axis, 0.21 * (sign + 1));  // vary the texture per face
      faces.push_back(face);
    }
  }
  return faces;
}

Scene makeBuiltinScene(const std::string& name, const Motion& motion, const CameraModel& camera,
                       uint64_t seed) {
  Scene scene;
  TextureOptions tex;
  tex.seed = seed;
  if (name == "shapes" || name == "checkerboard" || name == "stripes" || name == "blobs" ||
      name == "poster" || name == "photo" || name == "sparse") {
    std::shared_ptr<const Texture> texture;
    if (name == "shapes") texture = makeShapesTexture(tex);
    // A real photograph (CC0 gravel, docs/simulator.md §Photographs), 1 m per image: pebbles ~3 cm.
    if (name == "photo") texture = loadPhotoTexture(photoPath("gravel.png"), 1.0);
    if (name == "sparse") {
      TextureOptions sparse_tex = tex;
      sparse_tex.tile_m = 2.0;
      texture = makeSparseShapesTexture(sparse_tex, 1.5, 0.5);  // 4-8 polygons, ~15-30 corners in view
    }
    if (name == "checkerboard") texture = makeCheckerboardTexture(tex, 0.1);
    if (name == "stripes") texture = makeStripesTexture(tex, 0.1);
    if (name == "blobs") texture = makeBlobsTexture(tex);
    if (name == "poster") {
      // Poster-like: natural-image-like blobs with dark shapes printed over them (multiplied).
      const auto blobs = makeBlobsTexture(tex);
      const auto shapes = makeShapesTexture(tex);
      std::vector<float> mixed(blobs->pixels().size());
      for (std::size_t i = 0; i < mixed.size(); ++i) {
        mixed[i] = std::clamp(blobs->pixels()[i] * shapes->pixels()[i] / 0.9f, 0.02f, 1.0f);
      }
      texture =
          std::make_shared<Texture>(std::move(mixed), blobs->width(), blobs->height(), blobs->texelSize(),
                                    true, fmt::format("poster (blobs x shapes, seed {})", seed));
    }
    TexturedPlane plane = planeInFrontOfStart(motion, camera, 1.5, texture);
    plane.name = name;
    scene.planes.push_back(plane);
    scene.description =
        fmt::format("{}: one {:.2f} x {:.2f} m plane 1.5 m in front of the start pose, {}", name,
                    2 * plane.half_width, 2 * plane.half_height, texture->description());
    return scene;
  }
  if (name == "boxes") {
    const StampedPose start = motion.pose(motion.beginNs());
    const Eigen::Matrix3d R0 = rotationOf(start);
    const auto toWorld = [&](const Eigen::Vector3d& p_c) -> Eigen::Vector3d {
      return start.p_w_c + R0 * p_c;
    };
    TextureOptions wall_tex = tex;
    wall_tex.tile_m = 2.0;
    TexturedPlane wall = planeInFrontOfStart(motion, camera, 3.5, makeBlobsTexture(wall_tex));
    wall.name = "back wall";
    scene.planes.push_back(wall);
    TextureOptions box_tex = tex;
    box_tex.tile_m = 0.5;
    box_tex.texels = 512;
    const std::vector<std::shared_ptr<const Texture>> textures = {
        makeShapesTexture(box_tex), makeCheckerboardTexture(box_tex, 0.0625), makeBlobsTexture(box_tex)};
    struct BoxSpec {
      Eigen::Vector3d center_c;
      Eigen::Vector3d angles;
      double half;
    };
    const BoxSpec boxes[] = {{{-0.45, 0.15, 1.5}, {0.35, 0.6, 0.1}, 0.22},
                             {{0.35, -0.2, 1.2}, {-0.3, -0.5, 0.2}, 0.15},
                             {{0.25, 0.45, 2.3}, {0.5, 0.3, -0.2}, 0.3},
                             {{-0.2, -0.5, 2.6}, {0.2, 0.9, 0.4}, 0.25}};
    int k = 0;
    for (const BoxSpec& b : boxes) {
      const Eigen::Matrix3d R_w_b = R0 * lie::so3::exp(b.angles);
      std::vector<std::shared_ptr<const Texture>> rotated = {textures[k % 3], textures[(k + 1) % 3],
                                                             textures[(k + 2) % 3]};
      for (TexturedPlane& face : boxFaces(fmt::format("box {}", k), toWorld(b.center_c), R_w_b,
                                          Eigen::Vector3d::Constant(b.half), rotated)) {
        scene.planes.push_back(face);
      }
      ++k;
    }
    scene.description = fmt::format(
        "boxes: 4 textured cubes 0.3-0.6 m wide at 1.2-2.6 m before a {:.1f} x {:.1f} m "
        "blobs wall at 3.5 m",
        2 * wall.half_width, 2 * wall.half_height);
    return scene;
  }
  if (name == "grating") return makeGratingScene(motion, camera, seed);  // sim/grating_scene.hpp
  if (name == "room" || name == "photo-room") {
    // Sized from the motion: its bounding box plus 1.5 m on every side (DESIGN.md §5), at least 4 m wide.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
    for (const StampedPose& pose : coarseSamples(motion)) {
      lo = lo.cwiseMin(pose.p_w_c);
      hi = hi.cwiseMax(pose.p_w_c);
    }
    Eigen::Vector3d center = 0.5 * (lo + hi);
    Eigen::Vector3d half = (0.5 * (hi - lo)).array() + 1.5;
    half = half.cwiseMax(2.0);
    TextureOptions wall_tex = tex;
    wall_tex.tile_m = 1.5;
    TextureOptions floor_tex = tex;
    floor_tex.tile_m = 2.0;
    floor_tex.seed = seed + 1;
    std::vector<std::shared_ptr<const Texture>> textures;
    if (name == "room") {
      textures = {makeShapesTexture(wall_tex), makeBlobsTexture(wall_tex),   makeCheckerboardTexture(floor_tex, 0.25),
                  makeBlobsTexture(floor_tex), makeShapesTexture(floor_tex), makeCheckerboardTexture(wall_tex, 0.125)};
    } else {
      // Real photographs (docs/simulator.md §Photographs): textures 1 m per image, photos 1.5 m.
      textures = {loadPhotoTexture(photoPath("gravel.png"), 1.0),    loadPhotoTexture(photoPath("brick.png"), 1.0),
                  loadPhotoTexture(photoPath("grass.png"), 1.0),     loadPhotoTexture(photoPath("coffee.png"), 1.5),
                  loadPhotoTexture(photoPath("camera.png"), 1.5),    loadPhotoTexture(photoPath("astronaut.png"), 1.5)};
    }
    scene.planes = boxFaces("room", center, Eigen::Matrix3d::Identity(), half, textures);
    scene.description =
        fmt::format("{}: {:.1f} x {:.1f} x {:.1f} m {} box around the motion", name, 2 * half.x(), 2 * half.y(),
                    2 * half.z(), name == "room" ? "textured" : "photo-textured");
    return scene;
  }
  throw std::invalid_argument(
      fmt::format("unknown scene '{}' (built-in scenes: {})", name, fmt::join(sceneNames(), ", ")));
}

// ---- scene files -------------------------------------------------------------------------------------

namespace {

uint64_t lineOf(const YAML::Node& node) { return static_cast<uint64_t>(node.Mark().line) + 1; }

double number(const std::string& path, const YAML::Node& node, const std::string& what) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v))
      throw InputError::atLine(path, lineOf(node), fmt::format("'{}' is not finite", what));
    return v;
  } catch (const YAML::Exception&) {
    throw InputError::atLine(path, lineOf(node), fmt::format("'{}' must be a number", what));
  }
}

Eigen::VectorXd vectorOf(const std::string& path, const YAML::Node& parent, const char* key, int size,
                         bool required) {
  const YAML::Node node = parent[key];
  if (!node) {
    if (required) throw InputError::atLine(path, lineOf(parent), fmt::format("missing key '{}'", key));
    return Eigen::VectorXd();
  }
  if (!node.IsSequence() || static_cast<int>(node.size()) != size) {
    throw InputError::atLine(path, lineOf(node), fmt::format("'{}' must be a list of {} numbers", key, size));
  }
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = number(path, node[static_cast<std::size_t>(i)], key);
  return v;
}

}  // namespace

Scene loadSceneFile(const std::string& path, const Motion& motion, const CameraModel& camera, uint64_t seed) {
  if (!std::ifstream(path)) throw InputError(path, "cannot open file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError::atLine(path, static_cast<uint64_t>(e.mark.line) + 1, e.msg);
  }
  if (!root.IsMap()) throw InputError(path, "expected a map with 'planes'");
  Scene scene;
  scene.description = "scene file " + path;
  if (root["background"])
    scene.background = static_cast<float>(number(path, root["background"], "background"));
  std::string frame = "start";
  if (root["frame"]) frame = root["frame"].as<std::string>();
  if (frame != "start" && frame != "world") {
    throw InputError::atLine(path, lineOf(root["frame"]),
                             fmt::format("frame must be 'start' or 'world', got '{}'", frame));
  }
  const StampedPose start = motion.pose(motion.beginNs());
  const Eigen::Matrix3d R = frame == "start" ? rotationOf(start) : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t = frame == "start" ? start.p_w_c : Eigen::Vector3d::Zero();
  const YAML::Node planes = root["planes"];
  if (!planes || !planes.IsSequence() || planes.size() == 0) {
    throw InputError::atLine(path, lineOf(root), "missing or empty 'planes' list");
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  int index = 0;
  for (const YAML::Node& p : planes) {
    TexturedPlane plane;
    plane.name = p["name"] ? p["name"].as<std::string>() : fmt::format("plane {}", index);
    const Eigen::Vector3d center = vectorOf(path, p, "center", 3, true);
    Eigen::Vector3d normal = vectorOf(path, p, "normal", 3, true);
    if (normal.norm() < 1e-9)
      throw InputError::atLine(path, lineOf(p["normal"]), "'normal' must not be zero");
    normal.normalize();
    Eigen::Vector3d u = Eigen::Vector3d::UnitX();
    if (p["u_axis"]) u = vectorOf(path, p, "u_axis", 3, true);
    u -= u.dot(normal) * normal;
    if (u.norm() < 1e-6) {
      u = std::fabs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
      u -= u.dot(normal) * normal;
    }
    u.normalize();
    const Eigen::Vector3d v = normal.cross(u);
    const Eigen::Vector2d size = vectorOf(path, p, "size", 2, true);
    if (!(size.x() > 0 && size.y() > 0))
      throw InputError::atLine(path, lineOf(p["size"]), "'size' must be positive");
    plane.center_w = t + R * center;
    plane.u_w = R * u;
    plane.v_w = R * v;
    plane.half_width = size.x() / 2;
    plane.half_height = size.y() / 2;
    TextureOptions tex;
    tex.seed = p["seed"] ? p["seed"].as<uint64_t>() : seed + static_cast<uint64_t>(index);
    if (p["tile"]) tex.tile_m = number(path, p["tile"], "tile");
    const std::string type = p["texture"] ? p["texture"].as<std::string>() : "shapes";
    const uint64_t line = p["texture"] ? lineOf(p["texture"]) : lineOf(p);
    try {
      if (type == "shapes") {
        plane.texture = makeShapesTexture(tex);
      } else if (type == "checkerboard") {
        plane.texture = makeCheckerboardTexture(tex, p["square"] ? number(path, p["square"], "square") : 0.1);
      } else if (type == "stripes") {
        plane.texture = makeStripesTexture(tex, p["period"] ? number(path, p["period"], "period") : 0.1);
      } else if (type == "blobs") {
        plane.texture = makeBlobsTexture(tex);
      } else if (type == "image") {
        if (!p["image"]) throw InputError::atLine(path, line, "texture 'image' needs an 'image' path");
        std::filesystem::path image = p["image"].as<std::string>();
        if (image.is_relative()) image = folder / image;
        plane.texture = loadImageTexture(image.string(), size.x());
        // Centre the image on the plane.
        plane.texture_origin_m =
            Eigen::Vector2d(-plane.texture->widthMeters() / 2, -plane.texture->heightMeters() / 2);
      } else {
        throw InputError::atLine(
            path, line,
            fmt::format("unknown texture '{}' (shapes, checkerboard, stripes, blobs, image)", type));
      }
    } catch (const std::invalid_argument& e) {
      throw InputError::atLine(path, line, e.what());
    }
    scene.planes.push_back(plane);
    ++index;
  }
  (void)camera;
  return scene;
}

}  // namespace asynevo::sim
