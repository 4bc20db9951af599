// LZ4-frame and Zstandard-frame decompression of AEDAT 4.0 packets (aedat4_decompress.hpp).
#include "aedat4_decompress.hpp"

#include <fmt/format.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <stdexcept>

namespace asynevo::io_detail::aedat4 {

namespace {

constexpr std::size_t kInitialOutput = std::size_t{1} << 16;

}  // namespace

Decompressor::Decompressor(Compression compression, std::size_t max_output)
    : compression_(compression), max_output_(max_output) {
  if (compression_ == Compression::kLz4 || compression_ == Compression::kLz4High) {
    if (LZ4F_isError(LZ4F_createDecompressionContext(&lz4_, LZ4F_VERSION))) throw std::bad_alloc();
  } else if (compression_ == Compression::kZstd || compression_ == Compression::kZstdHigh) {
    zstd_ = ZSTD_createDCtx();
    if (zstd_ == nullptr) throw std::bad_alloc();
  } else {
    throw std::logic_error("aedat4::Decompressor needs a compression");
  }
  out_.resize(kInitialOutput);
}

Decompressor::~Decompressor() {
  if (lz4_ != nullptr) LZ4F_freeDecompressionContext(lz4_);
  if (zstd_ != nullptr) ZSTD_freeDCtx(zstd_);
}

bool Decompressor::failWith(std::string message) {
  error_ = std::move(message);
  return false;
}

bool Decompressor::grow() {
  if (out_.size() >= max_output_)
    return failWith(fmt::format("the packet decompresses to more than the {} MiB limit", max_output_ >> 20));
  out_.resize(std::min(out_.size() * 2, max_output_));
  return true;
}

bool Decompressor::decompress(const uint8_t* in, std::size_t size) {
  size_ = 0;
  error_.clear();
  return lz4_ != nullptr ? lz4(in, size) : zstd(in, size);
}

bool Decompressor::lz4(const uint8_t* in, std::size_t size) {
  LZ4F_resetDecompressionContext(lz4_);
  std::size_t in_pos = 0;
  for (;;) {
    std::size_t src = size - in_pos;
    std::size_t dst = out_.size() - size_;
    const std::size_t hint = LZ4F_decompress(lz4_, out_.data() + size_, &dst, in + in_pos, &src, nullptr);
    if (LZ4F_isError(hint)) return failWith(std::string("LZ4 frame: ") + LZ4F_getErrorName(hint));
    in_pos += src;
    size_ += dst;
    if (hint == 0) break;  // the frame is complete
    if (size_ == out_.size()) {
      if (!grow()) return false;
    } else if (in_pos == size) {
      return failWith("LZ4 frame: the packet ends inside the frame (truncated or corrupt)");
    } else if (src == 0 && dst == 0) {
      return failWith("LZ4 frame: the decoder makes no progress (corrupt frame)");
    }
  }
  if (in_pos != size) return failWith(fmt::format("LZ4 frame: {} bytes follow the end of the frame", size - in_pos));
  return true;
}

bool Decompressor::zstd(const uint8_t* in, std::size_t size) {
  ZSTD_DCtx_reset(zstd_, ZSTD_reset_session_only);
  ZSTD_inBuffer input{in, size, 0};
  for (;;) {
    ZSTD_outBuffer output{out_.data(), out_.size(), size_};
    const std::size_t in_before = input.pos;
    const std::size_t out_before = size_;
    const std::size_t hint = ZSTD_decompressStream(zstd_, &output, &input);
    size_ = output.pos;
    if (ZSTD_isError(hint)) return failWith(std::string("Zstd frame: ") + ZSTD_getErrorName(hint));
    if (hint == 0) break;  // the frame is complete
    if (size_ == out_.size()) {
      if (!grow()) return false;
    } else if (input.pos == input.size) {
      return failWith("Zstd frame: the packet ends inside the frame (truncated or corrupt)");
    } else if (input.pos == in_before && size_ == out_before) {
      return failWith("Zstd frame: the decoder makes no progress (corrupt frame)");
    }
  }
  if (input.pos != size) return failWith(fmt::format("Zstd frame: {} bytes follow the end of the frame", size - input.pos));
  return true;
}

}  // namespace asynevo::io_detail::aedat4
