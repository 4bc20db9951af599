#include "asynevo/sim/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace asynevo::sim {

Renderer::Renderer(const CameraModel& camera, const Scene& scene) : camera_(camera), scene_(scene) {
  const int w = camera.width(), h = camera.height();
  const UndistortionTable<double> table = camera.undistortionTable<double>();
  rays_.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  const auto at = [&](int x, int y) { return table.at(std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1)); };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      Ray& ray =
          rays_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
      ray.valid = table.valid(x, y);
      if (!ray.valid) continue;
      const Eigen::Vector2d c = table.at(x, y);
      ray.x = c.x();
      ray.y = c.y();
      // Central differences of the table (one-sided at the border) give the ray change per pixel.
      const int xl = std::max(x - 1, 0), xr = std::min(x + 1, w - 1);
      const int yu = std::max(y - 1, 0), yd = std::min(y + 1, h - 1);
      const double dx = (at(xr, y) - at(xl, y)).norm() / std::max(xr - xl, 1);
      const double dy = (at(x, yd) - at(x, yu)).norm() / std::max(yd - yu, 1);
      ray.k = std::max(dx, dy) * std::sqrt(c.x() * c.x() + c.y() * c.y() + 1.0);
    }
  }
  if (scene.planes.size() > 65535) throw std::invalid_argument("a scene holds at most 65535 planes");
  tiles_x_ = (w + kTile - 1) / kTile;
  tiles_y_ = (h + kTile - 1) / kTile;
  tiles_.resize(static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y_));
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      Tile& tile = tiles_[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x_) + static_cast<std::size_t>(tx)];
      for (int y = ty * kTile; y < std::min(h, (ty + 1) * kTile); ++y) {
        for (int x = tx * kTile; x < std::min(w, (tx + 1) * kTile); ++x) {
          const Ray& ray = rays_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
          if (!ray.valid) continue;
          if (!tile.any_valid) {
            tile.x0 = tile.x1 = ray.x;
            tile.y0 = tile.y1 = ray.y;
            tile.any_valid = true;
          }
          tile.x0 = std::min(tile.x0, ray.x);
          tile.x1 = std::max(tile.x1, ray.x);
          tile.y0 = std::min(tile.y0, ray.y);
          tile.y1 = std::max(tile.y1, ray.y);
          tile.k_max = std::max(tile.k_max, ray.k);
        }
      }
    }
  }
}

Renderer::Frame Renderer::prepare(const StampedPose& T_w_c) const {
  Frame frame = prepareGeometry(T_w_c);
  frame.tile_begin.reserve(tiles_.size() + 1);
  frame.tile_planes.reserve(tiles_.size() * 2);
  for (const Tile& tile : tiles_) {
    frame.tile_begin.push_back(static_cast<uint32_t>(frame.tile_planes.size()));
    if (!tile.any_valid) continue;
    const double cx[4] = {tile.x0, tile.x1, tile.x0, tile.x1};
    const double cy[4] = {tile.y0, tile.y0, tile.y1, tile.y1};
    for (std::size_t i = 0; i < frame.planes.size(); ++i) {
      const Frame::Plane& p = frame.planes[i];
      // n·r is linear in (x, y): over the box its extremes are at the corners.
      double nr[4];
      bool keep = false;
      for (int c = 0; c < 4; ++c) nr[c] = p.n.x() * cx[c] + p.n.y() * cy[c] + p.n.z();
      const bool positive = nr[0] > 0;
      for (int c = 0; c < 4 && !keep; ++c) keep = std::fabs(nr[c]) < 1e-9 || (nr[c] > 0) != positive;
      if (!keep) {
        // Depth s = dn / (n·r) has one sign over the box: all behind the camera -> culled.
        if ((p.dn > 0) != positive && p.dn != 0) continue;
        double a_lo = 1e300, a_hi = -1e300, b_lo = 1e300, b_hi = -1e300, nr2_min = 1e300;
        for (int c = 0; c < 4; ++c) {
          const double s = p.dn / nr[c];
          const double a = s * (p.u.x() * cx[c] + p.u.y() * cy[c] + p.u.z()) - p.au;
          const double b = s * (p.v.x() * cx[c] + p.v.y() * cy[c] + p.v.z()) - p.bv;
          a_lo = std::min(a_lo, a);
          a_hi = std::max(a_hi, a);
          b_lo = std::min(b_lo, b);
          b_hi = std::max(b_hi, b);
          nr2_min = std::min(nr2_min, nr[c] * nr[c]);
        }
        // Candidates satisfy |a| < hw + fp/2 and |b| < hh + fp/2 with fp <= |dn| k_max / min (n·r)²; a small
        // relative and absolute slack keeps the bound safe against rounding.
        const double margin = 0.5 * std::fabs(p.dn) * tile.k_max / nr2_min * 1.001 + 1e-9;
        const double slack_a = 1e-9 * (std::fabs(a_lo) + std::fabs(a_hi) + p.half_width);
        const double slack_b = 1e-9 * (std::fabs(b_lo) + std::fabs(b_hi) + p.half_height);
        const double ra = p.half_width + margin + slack_a, rb = p.half_height + margin + slack_b;
        keep = a_hi > -ra && a_lo < ra && b_hi > -rb && b_lo < rb;
      }
      if (keep) frame.tile_planes.push_back(static_cast<uint16_t>(i));
    }
  }
  frame.tile_begin.push_back(static_cast<uint32_t>(frame.tile_planes.size()));
  return frame;
}

Renderer::Frame Renderer::prepareGeometry(const StampedPose& T_w_c) const {
  Frame frame;
  const Eigen::Matrix3d R_c_w = T_w_c.q_w_c.toRotationMatrix().transpose();
  for (const TexturedPlane& p : scene_.planes) {
    Frame::Plane fp;
    const Eigen::Vector3d o = R_c_w * (p.center_w - T_w_c.p_w_c);
    fp.n = R_c_w * p.normal();
    fp.u = R_c_w * p.u_w;
    fp.v = R_c_w * p.v_w;
    fp.dn = fp.n.dot(o);
    fp.au = fp.u.dot(o);
    fp.bv = fp.v.dot(o);
    fp.half_width = p.half_width;
    fp.half_height = p.half_height;
    fp.source = &p;
    frame.planes.push_back(fp);
  }
  return frame;
}

float Renderer::shade(const Frame& frame, const Ray& ray, const uint16_t* planes_begin,
                      const uint16_t* planes_end) const {
  // Up to two candidates, nearest first: planes hit, or missed by less than half a pixel.
  struct Candidate {
    double depth = 1e300;
    double a = 0, b = 0, footprint = 0, coverage = 0;
    const Frame::Plane* plane = nullptr;
  };
  Candidate first, second;
  for (const uint16_t* index = planes_begin; index != planes_end; ++index) {
    const Frame::Plane& p = frame.planes[*index];
    const double nr = p.n.x() * ray.x + p.n.y() * ray.y + p.n.z();
    if (std::fabs(nr) < 1e-12) continue;
    const double s = p.dn / nr;  // depth Z of the hit (ray has z = 1)
    if (!(s > 1e-6)) continue;
    const double a = s * (p.u.x() * ray.x + p.u.y() * ray.y + p.u.z()) - p.au;
    const double b = s * (p.v.x() * ray.x + p.v.y() * ray.y + p.v.z()) - p.bv;
    const double footprint = s * ray.k / std::fabs(nr);
    // Signed distance to the rectangle's border in pixels (positive inside).
    const double inside_m = std::min(p.half_width - std::fabs(a), p.half_height - std::fabs(b));
    const double inside_px = inside_m / footprint;
    if (inside_px <= -0.5) continue;
    Candidate c{s, a, b, footprint, std::min(1.0, inside_px + 0.5), &p};
    if (s < first.depth) {
      second = first;
      first = c;
    } else if (s < second.depth) {
      second = c;
    }
  }
  const auto sample = [](const Candidate& c) {
    const TexturedPlane& src = *c.plane->source;
    return src.intensity_scale *
           src.texture->sample(c.a - src.texture_origin_m.x(), c.b - src.texture_origin_m.y(), c.footprint);
  };
  const float background = scene_.background;
  if (!first.plane) return background;
  const float front = sample(first);
  if (first.coverage >= 1.0) return front;
  float behind = background;
  if (second.plane) {
    const float back = sample(second);
    behind =
        static_cast<float>(second.coverage) * back + static_cast<float>(1 - second.coverage) * background;
  }
  return static_cast<float>(first.coverage) * front + static_cast<float>(1 - first.coverage) * behind;
}

void Renderer::render(const Frame& frame, float* image, int row_begin, int row_end) const {
  const auto w = static_cast<std::size_t>(camera_.width());
  if (frame.tile_begin.size() != tiles_.size() + 1)
    throw std::invalid_argument("Renderer::render needs a frame made by prepare()");
  const uint16_t* planes = frame.tile_planes.data();
  for (int y = row_begin; y < row_end; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    const std::size_t tile_row = static_cast<std::size_t>(y / kTile) * static_cast<std::size_t>(tiles_x_);
    for (std::size_t x = 0; x < w; ++x) {
      const Ray& ray = rays_[row + x];
      const std::size_t t = tile_row + x / kTile;
      image[row + x] = ray.valid ? shade(frame, ray, planes + frame.tile_begin[t], planes + frame.tile_begin[t + 1])
                                 : scene_.background;
    }
  }
}

std::vector<float> Renderer::render(const StampedPose& T_w_c) const {
  std::vector<float> image(rays_.size());
  render(prepare(T_w_c), image.data(), 0, camera_.height());
  return image;
}

void Renderer::sparseHits(const StampedPose& T_w_c, int stride, std::vector<Eigen::Vector2d>& pixels,
                          std::vector<Eigen::Vector3d>& points_w) const {
  pixels.clear();
  points_w.clear();
  const Frame frame = prepareGeometry(T_w_c);
  const Eigen::Matrix3d R_w_c = T_w_c.q_w_c.toRotationMatrix();
  const int w = camera_.width(), h = camera_.height();
  const auto visit = [&](int x, int y) {
    const Ray& ray =
        rays_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
    if (!ray.valid) return;
    double best = 1e300;
    for (const Frame::Plane& p : frame.planes) {
      const double nr = p.n.x() * ray.x + p.n.y() * ray.y + p.n.z();
      if (std::fabs(nr) < 1e-12) continue;
      const double s = p.dn / nr;
      if (!(s > 1e-6) || s >= best) continue;
      const double a = s * (p.u.x() * ray.x + p.u.y() * ray.y + p.u.z()) - p.au;
      const double b = s * (p.v.x() * ray.x + p.v.y() * ray.y + p.v.z()) - p.bv;
      if (std::fabs(a) > p.half_width || std::fabs(b) > p.half_height) continue;
      best = s;
    }
    if (best == 1e300) return;
    pixels.emplace_back(x, y);
    points_w.push_back(T_w_c.p_w_c + R_w_c * (best * Eigen::Vector3d(ray.x, ray.y, 1.0)));
  };
  for (int y = 0; y < h; y += stride) {
    for (int x = 0; x < w; x += stride) visit(x, y);
    visit(w - 1, y);
  }
  for (int x = 0; x < w; x += stride) visit(x, h - 1);
  visit(w - 1, h - 1);
}

}  // namespace asynevo::sim
