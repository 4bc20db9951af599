#include "asynevo/frames/frame_folder.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::frames {

std::vector<FrameEntry> readFrameList(const std::string& dir) {
  const std::filesystem::path list = std::filesystem::path(dir) / "images.txt";
  std::ifstream in(list);
  if (!in) {
    throw InputError(list.string(),
                     "no frame list: a frame folder holds images.txt ('t path' per frame), as written by "
                     "'asynevo simulate --frame-rate HZ'");
  }
  std::vector<FrameEntry> frames;
  std::string line;
  uint64_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t_s = 0;
    std::string path;
    if (!(fields >> t_s >> path) || !std::isfinite(t_s))
      throw InputError::atLine(list.string(), number, "expected 't path' (seconds, image file)");
    FrameEntry frame{secondsToNs(t_s), (std::filesystem::path(dir) / path).string()};
    if (!frames.empty() && frame.t_ns <= frames.back().t_ns)
      throw InputError::atLine(
          list.string(), number,
          fmt::format("time {} s does not increase (previous {} s)", t_s, nsToSeconds(frames.back().t_ns)));
    if (!std::filesystem::is_regular_file(frame.path))
      throw InputError::atLine(list.string(), number,
                               fmt::format("image file {} does not exist", frame.path));
    frames.push_back(std::move(frame));
  }
  if (frames.empty()) throw InputError(list.string(), "lists no frame");
  return frames;
}

cv::Mat loadFrame(const FrameEntry& frame, int width, int height) {
  cv::Mat image = cv::imread(frame.path, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw InputError(frame.path, "cannot read the image (not an image file OpenCV reads)");
  if (width > 0 && height > 0 && (image.cols != width || image.rows != height))
    throw InputError(frame.path,
                     fmt::format("image is {}x{} pixels, expected {}x{} (the first frame's or the "
                                 "calibration's size)",
                                 image.cols, image.rows, width, height));
  return image;
}

}  // namespace asynevo::frames
