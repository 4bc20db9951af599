#pragma once
// A folder of intensity frames in the ECD layout: `images.txt` lists `t path` (t in seconds, the path
// relative to the folder, e.g. `images/frame_00000000.png`), one frame per line, times increasing.
// 'asynevo simulate --frame-rate HZ' writes it (docs/simulator.md); ECD sequences ship it.

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace asynevo::frames {

struct FrameEntry {
  int64_t t_ns = 0;
  std::string path;  ///< full path of the image file
};

/// Reads `dir`/images.txt. Throws InputError naming images.txt when it is missing, or images.txt and the
/// line for a malformed line, a time that does not increase, or an image file that does not exist.
std::vector<FrameEntry> readFrameList(const std::string& dir);

/// Loads a frame as 8-bit grey. Throws InputError naming the image when it cannot be read, or when
/// `width` × `height` (both > 0) is given and the image has another size.
cv::Mat loadFrame(const FrameEntry& frame, int width = 0, int height = 0);

}  // namespace asynevo::frames
