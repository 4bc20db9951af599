#pragma once
// DSEC's rectification map (docs/reference/formats.md#rectification): `rectify_map.h5` beside a sequence's
// `events.h5` holds one dataset `rectify_map` of shape (height, width, 2), 32-bit floats, indexed [y, x] by a
// raw pixel and holding its [x, y] in the rectified camera (DSEC's camRect0 / camRect3: undistorted and
// rotated by R_rect, intrinsics in cam_to_cam.yaml). Layout from https://dsec.ifi.uzh.ch/data-format/ and
// the README and Sequence.rectify_events (scripts/dataset/sequence.py) of uzh-rpg/DSEC (cam0 left event camera,
// cam3 right).
//
// Events carry integer pixels (core/event.hpp), so each raw pixel's target is rounded to the nearest pixel
// (halves away from zero) once, when the map is loaded; a target outside the sensor drops the pixel's
// events, which the reader counts (ReaderStats::rectified_outside).

#include <cstdint>
#include <string>
#include <vector>

namespace asynevo::io_detail {

/// The rectification map's file name in a DSEC sequence folder (events/left/rectify_map.h5) and its dataset.
inline constexpr const char* kRectifyMapFile = "rectify_map.h5";
inline constexpr const char* kRectifyMapDataset = "rectify_map";

/// `rectify_map.h5` in the folder of `events_path` when it exists, else "".
std::string rectifyMapBeside(const std::string& events_path);

class RectifyMap {
 public:
  /// Reads and checks the map for a `width` x `height` sensor (`size_origin` names where that size came from,
  /// for messages). Throws InputError naming `path` and the dataset for a missing file or dataset, a shape
  /// other than (height, width, 2), values that are not floating point, or a NaN or infinite entry (named by
  /// its [y, x]).
  RectifyMap(const std::string& path, int width, int height, const std::string& size_origin);

  /// The rectified pixel of raw pixel (x, y) (inside the sensor); false when it is outside the sensor.
  bool map(int x, int y, uint16_t& x_rect, uint16_t& y_rect) const {
    const uint32_t target =
        target_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
    if (target == kNoPixel) return false;
    x_rect = static_cast<uint16_t>(target % static_cast<uint32_t>(width_));
    y_rect = static_cast<uint16_t>(target / static_cast<uint32_t>(width_));
    return true;
  }
  /// Raw pixels whose rectified pixel is outside the sensor (their events are dropped).
  uint64_t pixelsOutside() const { return pixels_outside_; }

 private:
  int width_ = 0;
  static constexpr uint32_t kNoPixel = 0xFFFFFFFFu;  // (65535·65535 < 2^32 - 1: no pixel index is this)
  std::vector<uint32_t> target_;  ///< per raw pixel (row-major): y_rect·width + x_rect, or kNoPixel (outside)
  uint64_t pixels_outside_ = 0;
};

}  // namespace asynevo::io_detail
