#pragma once
// Textures for the simulator's planes: a grey-level image in [0, 1] with a physical texel size and a
// mip-map pyramid, sampled trilinearly with a level chosen from the pixel footprint (Williams,
// "Pyramidal parametrics", SIGGRAPH 1983). Without this pre-filtering, texture detail smaller than a
// pixel would flicker as the camera moves and create spurious events.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace asynevo::sim {

class Texture {
 public:
  /// `pixels`: row-major width*height intensities in [0, 1]; `texel_m`: size of one texel in metres;
  /// `repeat`: tile the texture over the plane (otherwise the border texels extend it).
  Texture(std::vector<float> pixels, int width, int height, double texel_m, bool repeat,
          std::string description);

  /// Intensity at plane coordinates (u, v) in metres (u along the image rows, v down the columns, the
  /// texture's (0,0) corner at u = v = 0), pre-filtered for a pixel footprint of `footprint_m` metres.
  float sample(double u_m, double v_m, double footprint_m) const;

  int width() const { return levels_.front().width; }
  int height() const { return levels_.front().height; }
  double texelSize() const { return texel_m_; }
  /// Size of the texture (one tile) in metres.
  double widthMeters() const { return texel_m_ * width(); }
  double heightMeters() const { return texel_m_ * height(); }
  bool repeats() const { return repeat_; }
  int levelCount() const { return static_cast<int>(levels_.size()); }
  const std::string& description() const { return description_; }
  /// Level-0 intensities (row-major).
  const std::vector<float>& pixels() const { return levels_.front().data; }

 private:
  struct Level {
    int width = 0;
    int height = 0;
    double texel_u = 0;  // metres per texel along u and v at this level
    double texel_v = 0;
    double inv_texel_u = 0, inv_texel_v = 0;
    int mask_x = -1, mask_y = -1;  // width-1 / height-1 for power-of-two sizes (fast wrap), else -1
    std::vector<float> data;
  };
  float bilinear(const Level& level, double u_m, double v_m) const;

  std::vector<Level> levels_;
  double texel_m_;
  bool repeat_;
  std::string description_;
};

/// Procedural textures (all tile seamlessly; sizes in metres; deterministic for a seed). Intensities:
/// dark 0.1, bright 0.9 unless stated.
struct TextureOptions {
  double tile_m = 1.0;  ///< side of one tile
  int texels = 1024;    ///< texels per tile side (a power of two)
  uint64_t seed = 1;
};
/// Random dark polygons and ellipses on white, like the ECD "shapes" poster (about 12 per m²,
/// 5–15 cm, grey levels 0.05–0.35 on 0.9).
std::shared_ptr<const Texture> makeShapesTexture(const TextureOptions& options);
/// Sparse texture: `per_m2` irregular dark polygons (3-5 corners, 10-20 cm across, grey 0.05-0.35) per m²
/// on white (0.9), centres at least `min_separation_m` apart (fewer when they do not fit).
std::shared_ptr<const Texture> makeSparseShapesTexture(const TextureOptions& options, double per_m2 = 1.5,
                                                       double min_separation_m = 0.5);
/// Checkerboard with `square_m` squares (rounded so a whole number of squares fits in the tile).
std::shared_ptr<const Texture> makeCheckerboardTexture(const TextureOptions& options, double square_m = 0.1);
/// Vertical square-wave stripes (varying along u) with period `period_m` (rounded to fit the tile).
std::shared_ptr<const Texture> makeStripesTexture(const TextureOptions& options, double period_m = 0.1);
/// A grating of dark rectangles repeated with period `period_m` along u and v (rounded so a whole number
/// of periods fits in the tile): in each period × period cell, one `dark` block of half the period in
/// both directions at the cell's corner, on `bright`. Periodic along u like stripes, but with corners.
std::shared_ptr<const Texture> makeGratingTexture(const TextureOptions& options, double period_m,
                                                  float dark = 0.3f, float bright = 0.7f);
/// Multi-scale smooth noise ("blobs"): octaves of blurred white noise with amplitude ∝ scale, a
/// natural-image-like 1/f spectrum, stretched to [0.05, 0.95].
std::shared_ptr<const Texture> makeBlobsTexture(const TextureOptions& options);
/// Loads a PNG/JPEG (any format OpenCV reads) as grey levels; `width_m` is its physical width. The
/// texture does not repeat. Throws InputError when the file cannot be read.
std::shared_ptr<const Texture> loadImageTexture(const std::string& path, double width_m);
/// Loads a photograph as a repeating texture: grey levels mapped to [0.05, 0.95], the image `image_width_m`
/// wide, mirror-tiled (2x2: the image and its flips), so it repeats every 2 image widths without seams.
/// Throws InputError when the file cannot be read.
std::shared_ptr<const Texture> loadPhotoTexture(const std::string& path, double image_width_m);

}  // namespace asynevo::sim
