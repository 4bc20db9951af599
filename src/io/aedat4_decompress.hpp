#pragma once
// Decompression of AEDAT 4.0 packets: "each packet is one compressed frame" of the LZ4 frame format
// (compression LZ4 and LZ4 high) or of the Zstandard frame format (Zstd and Zstd high), through Debian's
// liblz4-dev and libzstd-dev (https://docs.inivation.com/software/software-advanced-usage/file-formats/
// aedat-4.0.html). The output buffer is reused from packet to packet and grows only up to a limit, so a
// corrupt or hostile frame cannot make the reader allocate without bound.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "aedat4_header.hpp"

struct LZ4F_dctx_s;
struct ZSTD_DCtx_s;

namespace asynevo::io_detail::aedat4 {

class Decompressor {
 public:
  /// `compression` must not be kNone. `max_output` bounds one packet's decompressed size.
  Decompressor(Compression compression, std::size_t max_output);
  ~Decompressor();
  Decompressor(const Decompressor&) = delete;
  Decompressor& operator=(const Decompressor&) = delete;

  /// Decompresses one whole frame `in[0..size)`. Returns true with the result in data()/size(), or false
  /// with error() describing the problem (corrupt data, a frame that ends early or is followed by other
  /// bytes, an output larger than the limit).
  bool decompress(const uint8_t* in, std::size_t size);
  const uint8_t* data() const { return out_.data(); }
  std::size_t size() const { return size_; }
  const std::string& error() const { return error_; }

 private:
  bool lz4(const uint8_t* in, std::size_t size);
  bool zstd(const uint8_t* in, std::size_t size);
  /// Makes room for more output; false (with error_) at the limit.
  bool grow();
  bool failWith(std::string message);

  Compression compression_;
  std::size_t max_output_;
  LZ4F_dctx_s* lz4_ = nullptr;
  ZSTD_DCtx_s* zstd_ = nullptr;
  std::vector<uint8_t> out_;  ///< never shrinks; size_ bytes of it are valid
  std::size_t size_ = 0;
  std::string error_;
};

}  // namespace asynevo::io_detail::aedat4
