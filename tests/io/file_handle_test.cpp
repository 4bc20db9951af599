// The read-buffer size of the streaming readers (asynevo/io/file_handle.hpp): a short file gets a short
// buffer, so opening many small files (the fuzz harnesses, a folder of slices) does not cost 1 MiB each.
#include "asynevo/io/file_handle.hpp"

#include <gtest/gtest.h>

#include <string>

#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

constexpr std::size_t kLargest = std::size_t{1} << 20;

TEST(ReadBufferBytes, AShortFileGetsItsSizePlusOneAboveTheSmallest) {
  const TempDir dir;
  EXPECT_EQ(readBufferBytes(dir.write("empty.txt", ""), kLargest), 4096u);
  EXPECT_EQ(readBufferBytes(dir.write("small.txt", std::string(100, 'x')), kLargest), 4096u);
  EXPECT_EQ(readBufferBytes(dir.write("mid.txt", std::string(10000, 'x')), kLargest), 10001u);
  EXPECT_EQ(readBufferBytes(dir.write("mid.txt", std::string(10000, 'x')), kLargest, 64), 10001u);
  EXPECT_EQ(readBufferBytes(dir.write("tiny.txt", "ab"), kLargest, 1), 3u);
}

TEST(ReadBufferBytes, ALargeFileOrOneWithoutASizeGetsTheLargest) {
  const TempDir dir;
  EXPECT_EQ(readBufferBytes(dir.write("big.txt", std::string(kLargest + 10, 'x')), kLargest), kLargest);
  EXPECT_EQ(readBufferBytes(dir.file("missing.txt"), kLargest), kLargest);
  EXPECT_EQ(readBufferBytes(dir.path().string(), kLargest), kLargest);  // a directory has no file size
  EXPECT_EQ(readBufferBytes(dir.write("small.txt", "abc"), 1000, 4096), 1000u);  // never above the largest
}

// The readers still read a file that fits the buffer exactly, to its last line without a newline.
TEST(ReadBufferBytes, AnEcdFileWhoseLastLineHasNoNewlineIsReadWhole) {
  const TempDir dir;
  const std::string path = dir.write("events.txt", "0.000001 1 2 1\n0.000002 3 4 0\n0.000003 5 6 1");
  ReaderOptions options;
  options.format = "ecd";
  auto reader = openEventReader(path, options);
  EventPacket packet;
  std::size_t events = 0;
  while (reader->read(packet)) events += packet.size();
  EXPECT_EQ(events, 3u);
}

}  // namespace
}  // namespace asynevo
