#pragma once
// Little-endian integers at any address of a byte buffer, whatever the host's byte order (the binary
// formats the readers parse store theirs little-endian: ROS bags, Prophesee EVT/DAT, Blosc headers).

#include <cstdint>

namespace asynevo::io_detail {

inline uint16_t load16(const unsigned char* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t load32(const unsigned char* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}
inline uint64_t load64(const unsigned char* p) {
  return load32(p) | (static_cast<uint64_t>(load32(p + 4)) << 32);
}

}  // namespace asynevo::io_detail
