// Frame folders (frames/frame_folder.hpp): the layout 'asynevo simulate --frame-rate' writes, and the
// errors a bad folder gives, each naming the file.
#include "asynevo/frames/frame_folder.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"

namespace asynevo::frames {
namespace {

using asynevo::testing::TempDir;

void writeImage(const std::string& path, int width, int height) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  ASSERT_TRUE(cv::imwrite(path, cv::Mat(height, width, CV_8U, cv::Scalar(128))));
}

/// The message of the InputError `f` throws ("" when it does not throw one).
template <typename F>
std::string inputError(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrameFolder, ReadsTimesAndPaths) {
  const TempDir dir;
  writeImage(dir.file("images/frame_00000000.png"), 24, 18);
  writeImage(dir.file("images/frame_00000001.png"), 24, 18);
  std::ofstream(dir.file("images.txt")) << "# t path\n0.000000000 images/frame_00000000.png\n"
                                           "0.033333333 images/frame_00000001.png\n";
  const std::vector<FrameEntry> frames = readFrameList(dir.path().string());
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].t_ns, 33'333'333);
  EXPECT_EQ(frames[1].path, dir.file("images/frame_00000001.png"));
  const cv::Mat image = loadFrame(frames[0], 24, 18);
  EXPECT_EQ(image.cols, 24);
  EXPECT_EQ(image.at<uint8_t>(3, 5), 128);
}

TEST(FrameFolder, BadFoldersNameTheFile) {
  const TempDir dir;
  // No images.txt.
  EXPECT_NE(inputError([&] { readFrameList(dir.path().string()); }).find(dir.file("images.txt")),
            std::string::npos);
  // A listed image that does not exist: images.txt, its line and the image are named.
  std::ofstream(dir.file("images.txt")) << "0.0 images/missing.png\n";
  std::string message = inputError([&] { readFrameList(dir.path().string()); });
  EXPECT_NE(message.find(dir.file("images.txt")), std::string::npos) << message;
  EXPECT_NE(message.find("images.txt:1:"), std::string::npos) << message;
  EXPECT_NE(message.find("missing.png"), std::string::npos) << message;
  // A malformed line and a time going back.
  writeImage(dir.file("images/a.png"), 24, 18);
  std::ofstream(dir.file("images.txt")) << "0.1 images/a.png\nzero images/a.png\n";
  EXPECT_NE(inputError([&] { readFrameList(dir.path().string()); }).find("images.txt:2:"), std::string::npos);
  std::ofstream(dir.file("images.txt")) << "0.1 images/a.png\n0.05 images/a.png\n";
  EXPECT_NE(inputError([&] { readFrameList(dir.path().string()); }).find("does not increase"),
            std::string::npos);
  // An unreadable image and one of the wrong size name the image.
  std::ofstream(dir.file("images/broken.png")) << "not an image";
  message = inputError([&] { loadFrame({0, dir.file("images/broken.png")}); });
  EXPECT_NE(message.find(dir.file("images/broken.png")), std::string::npos) << message;
  message = inputError([&] { loadFrame({0, dir.file("images/a.png")}, 240, 180); });
  EXPECT_NE(message.find(dir.file("images/a.png")), std::string::npos) << message;
  EXPECT_NE(message.find("24x18"), std::string::npos) << message;
}

}  // namespace
}  // namespace asynevo::frames
