#include "asynevo/sim/texture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/sim/random.hpp"

namespace asynevo::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

std::vector<float> matToVector(const cv::Mat& m) {
  cv::Mat f;
  m.convertTo(f, CV_32F);
  std::vector<float> out(static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols));
  for (int r = 0; r < f.rows; ++r) {
    const float* row = f.ptr<float>(r);
    std::copy(row, row + f.cols, out.begin() + static_cast<std::ptrdiff_t>(r) * f.cols);
  }
  return out;
}

// Draws with 4x supersampling (fillPoly on a 4x canvas, then an area-average resize), so edges are
// anti-aliased at the texel level too.
constexpr int kSupersample = 4;

}  // namespace

Texture::Texture(std::vector<float> pixels, int width, int height, double texel_m, bool repeat,
                 std::string description)
    : texel_m_(texel_m), repeat_(repeat), description_(std::move(description)) {
  if (width <= 0 || height <= 0 ||
      pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw std::invalid_argument("texture size does not match its data");
  }
  if (!(texel_m > 0)) throw std::invalid_argument("texel size must be positive");
  Level base;
  base.width = width;
  base.height = height;
  base.texel_u = base.texel_v = texel_m;
  base.data = std::move(pixels);
  levels_.push_back(std::move(base));
  // Mip levels: 2x2 box average (odd sizes drop the last row/column's remainder by clamping).
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Level& prev = levels_.back();
    Level next;
    next.width = std::max(1, prev.width / 2);
    next.height = std::max(1, prev.height / 2);
    next.texel_u = prev.texel_u * prev.width / next.width;
    next.texel_v = prev.texel_v * prev.height / next.height;
    next.data.resize(static_cast<std::size_t>(next.width) * static_cast<std::size_t>(next.height));
    for (int y = 0; y < next.height; ++y) {
      for (int x = 0; x < next.width; ++x) {
        const int x0 = std::min(2 * x, prev.width - 1), x1 = std::min(2 * x + 1, prev.width - 1);
        const int y0 = std::min(2 * y, prev.height - 1), y1 = std::min(2 * y + 1, prev.height - 1);
        const auto at = [&](int xx, int yy) {
          return prev.data[static_cast<std::size_t>(yy) * static_cast<std::size_t>(prev.width) +
                           static_cast<std::size_t>(xx)];
        };
        next.data[static_cast<std::size_t>(y) * static_cast<std::size_t>(next.width) +
                  static_cast<std::size_t>(x)] = 0.25f * (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1));
      }
    }
    levels_.push_back(std::move(next));
  }
  for (Level& level : levels_) {
    level.inv_texel_u = 1.0 / level.texel_u;
    level.inv_texel_v = 1.0 / level.texel_v;
    level.mask_x = isPowerOfTwo(level.width) ? level.width - 1 : -1;
    level.mask_y = isPowerOfTwo(level.height) ? level.height - 1 : -1;
  }
}

float Texture::bilinear(const Level& level, double u_m, double v_m) const {
  // Texel centres at (i + 0.5) * texel.
  const double fx = u_m * level.inv_texel_u - 0.5;
  const double fy = v_m * level.inv_texel_v - 0.5;
  // floor() for |f| < 2^62 without a library call.
  auto ix = static_cast<int64_t>(fx);
  ix -= fx < static_cast<double>(ix) ? 1 : 0;
  auto iy = static_cast<int64_t>(fy);
  iy -= fy < static_cast<double>(iy) ? 1 : 0;
  const auto ax = static_cast<float>(fx - static_cast<double>(ix));
  const auto ay = static_cast<float>(fy - static_cast<double>(iy));
  int64_t x0, x1, y0, y1;
  if (repeat_) {
    if (level.mask_x >= 0 && level.mask_y >= 0) {
      x0 = ix & level.mask_x;
      x1 = (ix + 1) & level.mask_x;
      y0 = iy & level.mask_y;
      y1 = (iy + 1) & level.mask_y;
    } else {
      const auto wrap = [](int64_t i, int64_t n) {
        const int64_t m = i % n;
        return m < 0 ? m + n : m;
      };
      x0 = wrap(ix, level.width);
      x1 = wrap(ix + 1, level.width);
      y0 = wrap(iy, level.height);
      y1 = wrap(iy + 1, level.height);
    }
  } else {
    x0 = std::clamp<int64_t>(ix, 0, level.width - 1);
    x1 = std::clamp<int64_t>(ix + 1, 0, level.width - 1);
    y0 = std::clamp<int64_t>(iy, 0, level.height - 1);
    y1 = std::clamp<int64_t>(iy + 1, 0, level.height - 1);
  }
  const int64_t w = level.width;
  const float* d = level.data.data();
  const float top = d[y0 * w + x0] + ax * (d[y0 * w + x1] - d[y0 * w + x0]);
  const float bottom = d[y1 * w + x0] + ax * (d[y1 * w + x1] - d[y1 * w + x0]);
  return top + ay * (bottom - top);
}

float Texture::sample(double u_m, double v_m, double footprint_m) const {
  // Level of detail λ = log2(footprint / texel); trilinear between floor(λ) and floor(λ) + 1.
  const double lod = footprint_m > texel_m_ ? std::log2(footprint_m / texel_m_) : 0.0;
  const int last = static_cast<int>(levels_.size()) - 1;
  if (lod >= last) return bilinear(levels_[static_cast<std::size_t>(last)], u_m, v_m);
  const int l0 = static_cast<int>(lod);
  const auto a = static_cast<float>(lod - l0);
  const float c0 = bilinear(levels_[static_cast<std::size_t>(l0)], u_m, v_m);
  if (a <= 0.0f) return c0;
  const float c1 = bilinear(levels_[static_cast<std::size_t>(l0 + 1)], u_m, v_m);
  return c0 + a * (c1 - c0);
}

namespace {

/// Draws a filled polygon (corners relative to its centre, metres) centred at (cx, cy) on a canvas of
/// `px_per_m`, with its copies shifted by one tile so the texture wraps seamlessly.
void drawWrapped(cv::Mat& canvas, const std::vector<cv::Point2d>& corners, double cx, double cy, double tile_m,
                 double px_per_m, double grey) {
  for (int sx = -1; sx <= 1; ++sx) {
    for (int sy = -1; sy <= 1; ++sy) {
      std::vector<cv::Point> poly;
      for (const cv::Point2d& c : corners) {
        // 8 fractional bits (fillPoly's shift) for sub-pixel corner positions.
        poly.emplace_back(static_cast<int>(std::lround((cx + c.x + sx * tile_m) * px_per_m * 256)),
                          static_cast<int>(std::lround((cy + c.y + sy * tile_m) * px_per_m * 256)));
      }
      cv::fillPoly(canvas, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(grey), cv::LINE_8, 8);
    }
  }
}

}  // namespace

std::shared_ptr<const Texture> makeShapesTexture(const TextureOptions& options) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  const int n = options.texels;
  const int big = n * kSupersample;
  const double px_per_m = big / options.tile_m;
  cv::Mat canvas(big, big, CV_32F, cv::Scalar(0.9));
  Random rng(options.seed ^ 0x5348415045530000ULL);  // "SHAPES"
  const int count = std::max(1, static_cast<int>(std::lround(12 * options.tile_m * options.tile_m)));
  for (int k = 0; k < count; ++k) {
    const double cx = rng.uniform() * options.tile_m;
    const double cy = rng.uniform() * options.tile_m;
    const double radius = 0.025 + 0.05 * rng.uniform();  // 5–15 cm across
    const double grey = 0.05 + 0.3 * rng.uniform();
    const int kind = static_cast<int>(rng.uniform() * 5);  // 0 ellipse, 1..4 polygons of 3..6 corners
    const double rotation = rng.uniform() * 2 * kPi;
    std::vector<cv::Point2d> corners;
    if (kind == 0) {
      const double ratio = 0.5 + 0.5 * rng.uniform();
      for (int i = 0; i < 64; ++i) {
        const double a = 2 * kPi * i / 64;
        const double x = radius * std::cos(a), y = radius * ratio * std::sin(a);
        corners.emplace_back(x * std::cos(rotation) - y * std::sin(rotation),
                             x * std::sin(rotation) + y * std::cos(rotation));
      }
    } else {
      const int m = kind + 2;
      for (int i = 0; i < m; ++i) {
        const double a = rotation + 2 * kPi * i / m;
        corners.emplace_back(radius * std::cos(a), radius * std::sin(a));
      }
    }
    drawWrapped(canvas, corners, cx, cy, options.tile_m, px_per_m, grey);
  }
  cv::Mat small;
  cv::resize(canvas, small, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return std::make_shared<Texture>(matToVector(small), n, n, options.tile_m / n, true,
                                   fmt::format("shapes (tile {} m, seed {})", options.tile_m, options.seed));
}

std::shared_ptr<const Texture> makeSparseShapesTexture(const TextureOptions& options, double per_m2,
                                                       double min_separation_m) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  if (!(per_m2 > 0) || !(min_separation_m >= 0))
    throw std::invalid_argument("sparse shapes need a positive density and a non-negative separation");
  const int n = options.texels;
  const int big = n * kSupersample;
  const double tile = options.tile_m;
  const double px_per_m = big / tile;
  cv::Mat canvas(big, big, CV_32F, cv::Scalar(0.9));
  Random rng(options.seed ^ 0x5350415253450000ULL);  // "SPARSE"
  const int count = std::max(1, static_cast<int>(std::lround(per_m2 * tile * tile)));
  // Dart throwing: centres at least min_separation_m apart, distances measured across the tile's wrap.
  std::vector<cv::Point2d> centres;
  for (int attempt = 0; attempt < 10000 && static_cast<int>(centres.size()) < count; ++attempt) {
    const cv::Point2d c(rng.uniform() * tile, rng.uniform() * tile);
    bool free = true;
    for (const cv::Point2d& o : centres) {
      double dx = std::fabs(c.x - o.x), dy = std::fabs(c.y - o.y);
      dx = std::min(dx, tile - dx);
      dy = std::min(dy, tile - dy);
      if (dx * dx + dy * dy < min_separation_m * min_separation_m) {
        free = false;
        break;
      }
    }
    if (free) centres.push_back(c);
  }
  for (const cv::Point2d& c : centres) {
    const double radius = 0.05 + 0.05 * rng.uniform();  // 10-20 cm across
    const double grey = 0.05 + 0.3 * rng.uniform();
    const int corners_n = 3 + static_cast<int>(rng.uniform() * 3);  // polygons of 3..5 corners
    const double rotation = rng.uniform() * 2 * kPi;
    std::vector<cv::Point2d> corners;
    for (int i = 0; i < corners_n; ++i) {
      // Irregular polygons: corner angles and radii perturbed, so corners are not all alike.
      const double a = rotation + 2 * kPi * (i + 0.3 * (rng.uniform() - 0.5)) / corners_n;
      const double r = radius * (0.75 + 0.25 * rng.uniform());
      corners.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    drawWrapped(canvas, corners, c.x, c.y, tile, px_per_m, grey);
  }
  cv::Mat small;
  cv::resize(canvas, small, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return std::make_shared<Texture>(
      matToVector(small), n, n, tile / n, true,
      fmt::format("sparse shapes ({} polygons per {} m tile, >= {} m apart, seed {})", centres.size(), tile,
                  min_separation_m, options.seed));
}

std::shared_ptr<const Texture> makeCheckerboardTexture(const TextureOptions& options, double square_m) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  if (!(square_m > 0)) throw std::invalid_argument("checkerboard square size must be positive");
  const int n = options.texels;
  // An even number of squares per tile so the pattern wraps.
  const int squares = std::max(2, 2 * static_cast<int>(std::lround(options.tile_m / square_m / 2)));
  const double square = options.tile_m / squares;
  const int big = n * kSupersample;
  cv::Mat canvas(big, big, CV_32F);
  for (int y = 0; y < big; ++y) {
    for (int x = 0; x < big; ++x) {
      const double u = (x + 0.5) * options.tile_m / big, v = (y + 0.5) * options.tile_m / big;
      const int parity = (static_cast<int>(u / square) + static_cast<int>(v / square)) & 1;
      canvas.at<float>(y, x) = parity ? 0.1f : 0.9f;
    }
  }
  cv::Mat small;
  cv::resize(canvas, small, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return std::make_shared<Texture>(matToVector(small), n, n, options.tile_m / n, true,
                                   fmt::format("checkerboard (squares {:.4g} m)", square));
}

std::shared_ptr<const Texture> makeStripesTexture(const TextureOptions& options, double period_m) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  if (!(period_m > 0)) throw std::invalid_argument("stripe period must be positive");
  const int n = options.texels;
  const int periods = std::max(1, static_cast<int>(std::lround(options.tile_m / period_m)));
  const double period = options.tile_m / periods;
  const int big = n * kSupersample;
  cv::Mat canvas(big, big, CV_32F);
  for (int x = 0; x < big; ++x) {
    const double u = (x + 0.5) * options.tile_m / big;
    const float value = std::fmod(u, period) < period / 2 ? 0.9f : 0.1f;
    for (int y = 0; y < big; ++y) canvas.at<float>(y, x) = value;
  }
  cv::Mat small;
  cv::resize(canvas, small, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return std::make_shared<Texture>(matToVector(small), n, n, options.tile_m / n, true,
                                   fmt::format("stripes (period {:.4g} m)", period));
}

std::shared_ptr<const Texture> makeGratingTexture(const TextureOptions& options, double period_m, float dark,
                                                  float bright) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  if (!(period_m > 0)) throw std::invalid_argument("grating period must be positive");
  const int n = options.texels;
  const int periods = std::max(1, static_cast<int>(std::lround(options.tile_m / period_m)));
  const double period = options.tile_m / periods;
  const int big = n * kSupersample;
  cv::Mat canvas(big, big, CV_32F);
  for (int y = 0; y < big; ++y) {
    const bool dark_row = std::fmod((y + 0.5) * options.tile_m / big, period) < period / 2;
    for (int x = 0; x < big; ++x) {
      const bool dark_col = std::fmod((x + 0.5) * options.tile_m / big, period) < period / 2;
      canvas.at<float>(y, x) = dark_row && dark_col ? dark : bright;
    }
  }
  cv::Mat small;
  cv::resize(canvas, small, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return std::make_shared<Texture>(matToVector(small), n, n, options.tile_m / n, true,
                                   fmt::format("grating (period {:.4g} m, blocks {:.2g} on {:.2g})", period,
                                               dark, bright));
}

std::shared_ptr<const Texture> makeBlobsTexture(const TextureOptions& options) {
  if (!isPowerOfTwo(options.texels)) throw std::invalid_argument("texture size must be a power of two");
  const int n = options.texels;
  Random rng(options.seed ^ 0x424C4F4253000000ULL);  // "BLOBS"
  cv::Mat sum(n, n, CV_32F, cv::Scalar(0));
  // Octaves with blur sigma 1.5 cm .. 24 cm; amplitude ∝ sigma gives a 1/f-like spectrum. Each octave
  // is made on a coarse grid where its sigma is ~2 cells (white noise, wrap-padded Gaussian blur), then
  // upsampled bicubically with wrap padding, so large octaves cost no more than small ones and the
  // result tiles seamlessly.
  for (double sigma_m = 0.015; sigma_m <= 0.25; sigma_m *= 2) {
    const double sigma_full = sigma_m / (options.tile_m / n);  // in level-0 texels
    int m = n;
    while (m > 8 && sigma_full * m / n > 4.0) m /= 2;
    const double sigma_px = sigma_full * m / n;
    cv::Mat noise(m, m, CV_32F);
    for (int y = 0; y < m; ++y) {
      for (int x = 0; x < m; ++x) noise.at<float>(y, x) = static_cast<float>(rng.normal());
    }
    const int pad = static_cast<int>(std::ceil(4 * sigma_px));
    cv::Mat padded, blurred;
    cv::copyMakeBorder(noise, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
    cv::GaussianBlur(padded, blurred, cv::Size(0, 0), sigma_px, sigma_px, cv::BORDER_REFLECT);
    cv::Mat coarse = blurred(cv::Rect(pad, pad, m, m)).clone();
    cv::Mat octave;
    if (m == n) {
      octave = coarse;
    } else {
      const int factor = n / m;
      const int border = 2;
      cv::Mat wrapped, up;
      cv::copyMakeBorder(coarse, wrapped, border, border, border, border, cv::BORDER_WRAP);
      cv::resize(wrapped, up, cv::Size((m + 2 * border) * factor, (m + 2 * border) * factor), 0, 0,
                 cv::INTER_CUBIC);
      octave = up(cv::Rect(border * factor, border * factor, n, n)).clone();
    }
    cv::Scalar mean, stddev;
    cv::meanStdDev(octave, mean, stddev);
    sum += (octave - mean[0]) * (sigma_m / std::max(stddev[0], 1e-12));
  }
  double lo = 0, hi = 0;
  cv::minMaxLoc(sum, &lo, &hi);
  cv::Mat normalized = (sum - lo) * (0.9 / std::max(hi - lo, 1e-12)) + 0.05;
  return std::make_shared<Texture>(matToVector(normalized), n, n, options.tile_m / n, true,
                                   fmt::format("blobs (tile {} m, seed {})", options.tile_m, options.seed));
}

std::shared_ptr<const Texture> loadImageTexture(const std::string& path, double width_m) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw InputError(path, "cannot read image (not found or not a format OpenCV reads)");
  if (!(width_m > 0)) throw std::invalid_argument("image texture width must be positive");
  cv::Mat f;
  image.convertTo(f, CV_32F, 1.0 / 255.0);
  return std::make_shared<Texture>(
      matToVector(f), f.cols, f.rows, width_m / f.cols, false,
      fmt::format("image {} ({}x{} px, {} m wide)", path, f.cols, f.rows, width_m));
}

std::shared_ptr<const Texture> loadPhotoTexture(const std::string& path, double image_width_m) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw InputError(path, "cannot read image (not found or not a format OpenCV reads)");
  if (!(image_width_m > 0)) throw std::invalid_argument("image texture width must be positive");
  cv::Mat f;
  image.convertTo(f, CV_32F, 0.9 / 255.0, 0.05);  // [0, 255] -> [0.05, 0.95]
  // Mirror tile [I, flip_x(I); flip_y(I), flip_xy(I)]: periodic without seams.
  cv::Mat right, bottom, corner, top_row, bottom_row, tile;
  cv::flip(f, right, 1);
  cv::flip(f, bottom, 0);
  cv::flip(f, corner, -1);
  cv::hconcat(f, right, top_row);
  cv::hconcat(bottom, corner, bottom_row);
  cv::vconcat(top_row, bottom_row, tile);
  return std::make_shared<Texture>(
      matToVector(tile), tile.cols, tile.rows, image_width_m / f.cols, true,
      fmt::format("photo {} ({}x{} px, {} m wide, mirror-tiled)", path, f.cols, f.rows, image_width_m));
}

}  // namespace asynevo::sim
