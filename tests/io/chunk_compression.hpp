#pragma once
// Compressed-chunk payloads for ROS bag fixtures (tests, the bag benchmark, the fuzz seed maker): an
// LZ4 frame (liblz4) and a bzip2 stream (libbz2), as a bag's lz4 and bz2 chunks hold them.

#include <bzlib.h>
#include <lz4frame.h>

#include <string>

namespace asynevo::testing::bag {

inline std::string lz4(const std::string& in) {
  std::string out(LZ4F_compressFrameBound(in.size(), nullptr), '\0');
  out.resize(LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr));
  return out;
}

inline std::string bz2(const std::string& in) {
  std::string out(in.size() + in.size() / 100 + 700, '\0');  // libbz2's documented worst case
  auto n = static_cast<unsigned int>(out.size());
  std::string src = in;
  BZ2_bzBuffToBuffCompress(out.data(), &n, src.data(), static_cast<unsigned int>(src.size()), 9, 0, 0);
  out.resize(n);
  return out;
}

}  // namespace asynevo::testing::bag
