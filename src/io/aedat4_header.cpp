// AEDAT 4.0 header: version line, int32 size, IOHeader FlatBuffer (aedat4_header.hpp for the layout and
// the specification's address). The IOHeader is read as a size-prefixed FlatBuffer (the int32 is its size
// prefix) and verified with flatbuffers::Verifier before any field is read.
#include "aedat4_header.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <vector>

#include "aedat4_flatbuffers.hpp"
#include "asynevo/core/error.hpp"

namespace asynevo::io_detail::aedat4 {

namespace {

constexpr uint32_t kMaxHeaderBytes = 16u << 20;  // a real IOHeader is a few KiB (its XML info node)

}  // namespace

const char* compressionName(int32_t compression) {
  switch (compression) {
    case 0: return "none";
    case 1: return "LZ4";
    case 2: return "LZ4 high";
    case 3: return "Zstd";
    case 4: return "Zstd high";
    default: return "";
  }
}

Header readHeader(std::FILE* file, const std::string& path) {
  if (std::fseek(file, 0, SEEK_SET) != 0) throw InputError(path, "cannot seek to the start of the file");
  char magic[kMagicBytes];
  const std::size_t got = std::fread(magic, 1, kMagicBytes, file);
  if (std::ferror(file)) throw InputError(path, std::string("read error: ") + std::strerror(errno));
  if (got < kMagicBytes || std::memcmp(magic, kMagic, kMagicBytes) != 0) {
    const std::size_t shown = std::min<std::size_t>(std::string(magic, got).find('\r'), got);
    throw InputError::atByte(path, 0,
                             "not an AEDAT 4.0 file: it does not start with the version line '#!AER-DAT4.0\\r\\n'" +
                                 (got > 0 ? " (it starts with '" + std::string(magic, shown) + "')" : std::string()));
  }
  // The int32 size prefix and the IOHeader FlatBuffer, kept together so alignment is as written.
  std::vector<uint8_t> buffer(4);
  if (std::fread(buffer.data(), 1, 4, file) != 4)
    throw InputError::atByte(path, kMagicBytes, "truncated: the file ends before the IOHeader size");
  const uint32_t size = flatbuffers::ReadScalar<uint32_t>(buffer.data());
  if (size < 8 || size > kMaxHeaderBytes) {
    throw InputError::atByte(path, kMagicBytes,
                             fmt::format("IOHeader size {} is outside 8..{} bytes (corrupt header?)",
                                         static_cast<int32_t>(size), kMaxHeaderBytes));
  }
  buffer.resize(4 + static_cast<std::size_t>(size));
  const std::size_t body = std::fread(buffer.data() + 4, 1, size, file);
  if (body != size) {
    throw InputError::atByte(path, kMagicBytes + 4,
                             fmt::format("truncated: the IOHeader has {} of its {} bytes", body, size));
  }
  const uint64_t fb_offset = kMagicBytes + 4;  // the FlatBuffer's first byte in the file
  std::vector<uint64_t> scratch;
  const uint8_t* verified = verifySizePrefixed<IoHeaderTable>(buffer.data(), buffer.size(), scratch);
  if (verified == nullptr) {
    throw InputError::atByte(path, fb_offset,
                             "the IOHeader FlatBuffer fails verification (an offset or size points outside it: "
                             "corrupt header)");
  }
  const auto* table = flatbuffers::GetSizePrefixedRoot<IoHeaderTable>(verified);
  Header header;
  const int32_t compression = table->compression();
  if (compressionName(compression)[0] == '\0') {
    throw InputError::atByte(path, fb_offset,
                             fmt::format("unknown compression type {} in the IOHeader (known: 0 none, 1 LZ4, "
                                         "2 LZ4 high, 3 Zstd, 4 Zstd high)",
                                         compression));
  }
  header.compression = static_cast<Compression>(compression);
  header.data_offset = fb_offset + size;
  header.data_table_position = table->dataTablePosition();
  if (header.data_table_position != -1 && (header.data_table_position < 0 ||
                                            static_cast<uint64_t>(header.data_table_position) < header.data_offset)) {
    throw InputError::atByte(path, fb_offset,
                             fmt::format("the IOHeader places the data table at byte {}, inside the header "
                                         "(expected -1 or an offset after byte {})",
                                         header.data_table_position, header.data_offset));
  }
  const flatbuffers::String* info = table->infoNode();
  if (info == nullptr || info->size() == 0)
    throw InputError::atByte(path, fb_offset, "the IOHeader has no info node: the file does not say what its streams are");
  const auto xml_offset = static_cast<uint64_t>(reinterpret_cast<const uint8_t*>(info->c_str()) - verified);
  header.streams = parseStreams(info->str(), path, kMagicBytes + xml_offset);
  return header;
}

}  // namespace asynevo::io_detail::aedat4
