#include "hdf5_layout.hpp"

#include <fmt/format.h>

#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "asynevo/core/error.hpp"
#include "hdf5_handle.hpp"

// Byte layouts from the HDF5 File Format Specification, version 3.0: IV.A.1.a "Version 1 Data Object
// Header Prefix", IV.A.1.b "Version 2 Data Object Header Prefix", IV.A.2.i "The Data Layout Message" and
// IV.A.2.q "Object Header Continuation Message". Numbers are little-endian.

namespace asynevo::io_detail {

namespace {

constexpr unsigned kLayoutMessage = 0x0008;
constexpr unsigned kContinuationMessage = 0x0010;
constexpr unsigned kChunkedLayout = 2;
// A header is its first chunk plus one chunk per continuation message. Files HDF5 writes continue a
// header a few times; these bounds only stop a corrupt one from looping or allocating without end.
constexpr int kMaxHeaderChunks = 1024;
constexpr uint64_t kMaxHeaderChunkBytes = uint64_t{1} << 26;

// Where the header could not be read: the byte offset in the file and why.
struct HeaderError {
  uint64_t offset;
  std::string reason;
};

// A bounded view of bytes read from the file at `origin`.
class Cursor {
 public:
  Cursor(const std::vector<uint8_t>& bytes, uint64_t origin, std::size_t begin, std::size_t end)
      : bytes_(bytes), origin_(origin), pos_(begin), end_(end) {}

  std::size_t remaining() const { return end_ - pos_; }
  uint64_t offset() const { return origin_ + pos_; }

  // The next `n` (≤ 8) bytes as a little-endian number.
  uint64_t number(std::size_t n, const char* what) {
    require(n, what);
    uint64_t value = 0;
    for (std::size_t i = n; i-- > 0;) value = (value << 8) | bytes_[pos_ + i];
    pos_ += n;
    return value;
  }
  void skip(std::size_t n, const char* what) {
    require(n, what);
    pos_ += n;
  }
  // The next `n` bytes as a cursor of their own.
  Cursor take(std::size_t n, const char* what) {
    require(n, what);
    Cursor part(bytes_, origin_, pos_, pos_ + n);
    pos_ += n;
    return part;
  }

 private:
  void require(std::size_t n, const char* what) const {
    if (n > remaining())
      throw HeaderError{offset(), fmt::format("{} runs past the end of its header chunk", what)};
  }

  const std::vector<uint8_t>& bytes_;
  uint64_t origin_;
  std::size_t pos_, end_;
};

class FileBytes {
 public:
  explicit FileBytes(const std::string& path) : in_(path, std::ios::binary) {
    std::error_code error;
    size_ = std::filesystem::file_size(path, error);
    if (!in_ || error) throw HeaderError{0, "cannot read the file"};
  }
  std::vector<uint8_t> read(uint64_t offset, uint64_t length, const char* what) {
    if (offset > size_ || length > size_ - offset) {
      throw HeaderError{
          offset, fmt::format("{} of {} bytes lies past the end of the {}-byte file", what, length, size_)};
    }
    std::vector<uint8_t> bytes(length);
    in_.seekg(static_cast<std::streamoff>(offset));
    if (!in_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(length)))
      throw HeaderError{offset, fmt::format("cannot read {}", what)};
    return bytes;
  }

 private:
  std::ifstream in_;
  uint64_t size_ = 0;
};

// The value size in a layout message's data: the last chunk dimension. 0 unless chunked.
uint64_t layoutValueSize(Cursor data, unsigned address_bytes) {
  const uint64_t version = data.number(1, "the layout message");
  uint64_t layout_class = 0, dimensions = 0, dimension_bytes = 4;
  if (version == 1 || version == 2) {
    dimensions = data.number(1, "the layout message");
    layout_class = data.number(1, "the layout message");
    if (layout_class != kChunkedLayout) return 0;
    data.skip(5, "the layout message");
    data.skip(address_bytes, "the layout message's address");
  } else if (version == 3) {
    layout_class = data.number(1, "the layout message");
    if (layout_class != kChunkedLayout) return 0;
    dimensions = data.number(1, "the layout message");
    data.skip(address_bytes, "the layout message's address");
  } else if (version == 4) {
    layout_class = data.number(1, "the layout message");
    if (layout_class != kChunkedLayout) return 0;
    data.skip(1, "the layout message's flags");
    dimensions = data.number(1, "the layout message");
    dimension_bytes = data.number(1, "the layout message");
    if (dimension_bytes < 1 || dimension_bytes > 8)
      throw HeaderError{data.offset() - 1, fmt::format("chunk dimensions of {} bytes each", dimension_bytes)};
  } else {
    throw HeaderError{data.offset() - 1, fmt::format("data layout message of version {}", version)};
  }
  if (dimensions < 2)
    throw HeaderError{data.offset(), fmt::format("chunked layout of {} dimensions", dimensions)};
  uint64_t value_size = 0;
  for (uint64_t i = 0; i < dimensions; ++i) value_size = data.number(dimension_bytes, "a chunk dimension");
  return value_size;
}

struct HeaderChunk {
  uint64_t address, length;
};

// Scans one header chunk's messages: returns the layout's value size when the layout message is in it,
// and queues the chunks its continuation messages point to.
std::optional<uint64_t> scanMessages(Cursor messages, bool version2, bool creation_order,
                                     unsigned address_bytes, unsigned length_bytes, uint64_t base,
                                     std::deque<HeaderChunk>& pending) {
  const std::size_t prefix = version2 ? (creation_order ? 6 : 4) : 8;
  // Version 2 chunks may end in a gap smaller than a message prefix; version 1 messages are 8-byte aligned.
  while (messages.remaining() >= prefix) {
    const unsigned type = static_cast<unsigned>(messages.number(version2 ? 1 : 2, "a message type"));
    const uint64_t size = messages.number(2, "a message size");
    messages.skip(prefix - (version2 ? 3 : 4), "a message prefix");
    Cursor data = messages.take(size, "a message");
    if (type == kLayoutMessage) return layoutValueSize(data, address_bytes);
    if (type == kContinuationMessage) {
      const uint64_t address = data.number(address_bytes, "a continuation address");
      const uint64_t length = data.number(length_bytes, "a continuation length");
      pending.push_back({base + address, length});
    }
  }
  return std::nullopt;
}

uint64_t findLayoutValueSize(FileBytes& file, uint64_t header, uint64_t base, unsigned address_bytes,
                             unsigned length_bytes) {
  const std::vector<uint8_t> start = file.read(header, 16, "the object header's prefix");
  const bool version2 = std::memcmp(start.data(), "OHDR", 4) == 0;
  std::deque<HeaderChunk> pending;
  bool creation_order = false;
  if (version2) {
    Cursor prefix(start, header, 4, start.size());
    if (prefix.number(1, "the header version") != 2)
      throw HeaderError{header + 4, "an object header of an unknown version"};
    const uint64_t flags = prefix.number(1, "the header flags");
    creation_order = (flags & 0x04) != 0;
    std::size_t skipped = ((flags & 0x20) ? 16 : 0) + ((flags & 0x10) ? 4 : 0);
    const std::vector<uint8_t> more = file.read(header + 6 + skipped, 8, "the object header's prefix");
    Cursor size(more, header + 6 + skipped, 0, more.size());
    const uint64_t length = size.number(std::size_t{1} << (flags & 0x03), "the first chunk's size");
    const uint64_t first = header + 6 + skipped + (uint64_t{1} << (flags & 0x03));
    pending.push_back({first, length});
  } else {
    Cursor prefix(start, header, 0, start.size());
    if (prefix.number(1, "the header version") != 1)
      throw HeaderError{header, "an object header of an unknown version"};
    prefix.skip(7, "the header prefix");
    pending.push_back({header + 16, prefix.number(4, "the first chunk's size")});
  }
  for (int chunks = 0; !pending.empty(); ++chunks) {
    const HeaderChunk chunk = pending.front();
    pending.pop_front();
    if (chunks == kMaxHeaderChunks || chunk.length > kMaxHeaderChunkBytes)
      throw HeaderError{chunk.address, "an object header continued without end"};
    const std::vector<uint8_t> bytes = file.read(chunk.address, chunk.length, "an object header chunk");
    std::size_t begin = 0, end = bytes.size();
    // A version 2 continuation chunk is its signature, messages and a checksum (the first chunk's
    // checksum follows the length its prefix states).
    if (version2 && chunks > 0) {
      if (bytes.size() < 8 || std::memcmp(bytes.data(), "OCHK", 4) != 0)
        throw HeaderError{chunk.address, "a header continuation without its OCHK signature and checksum"};
      begin = 4;
      end -= 4;
    }
    const std::optional<uint64_t> found =
        scanMessages(Cursor(bytes, chunk.address, begin, end), version2, creation_order, address_bytes,
                     length_bytes, base, pending);
    if (found) return *found;
  }
  throw HeaderError{header, "no data layout message in the dataset's object header"};
}

}  // namespace

uint64_t h5ChunkValueSize(const std::string& path, hid_t dataset, const std::string& name) {
  const H5PropertyList create(H5Dget_create_plist(dataset));
  if (!create.valid())
    throw InputError(path, fmt::format("cannot read the layout of dataset '{}' (corrupt file?)", name));
  if (H5Pget_layout(create.get()) != H5D_CHUNKED) return 0;
  H5O_info_t info{};
  const H5Handle<H5Fclose> file(H5Iget_file_id(dataset));
  const H5PropertyList file_create(file.valid() ? H5Fget_create_plist(file.get()) : -1);
  std::size_t address_bytes = 0, length_bytes = 0;
  hsize_t userblock = 0;
  if (H5Oget_info2(dataset, &info, H5O_INFO_BASIC) < 0 || !file_create.valid() ||
      H5Pget_sizes(file_create.get(), &address_bytes, &length_bytes) < 0 ||
      H5Pget_userblock(file_create.get(), &userblock) < 0 || address_bytes < 2 || address_bytes > 8 ||
      length_bytes < 2 || length_bytes > 8) {
    throw InputError(path,
                     fmt::format("cannot locate the object header of dataset '{}' (corrupt file?)", name));
  }
  try {
    // Addresses count from the base address, which is where the superblock starts: after the user block.
    FileBytes bytes(path);
    return findLayoutValueSize(bytes, userblock + info.addr, userblock, static_cast<unsigned>(address_bytes),
                               static_cast<unsigned>(length_bytes));
  } catch (const HeaderError& error) {
    throw InputError::atByte(
        path, error.offset,
        fmt::format("cannot read the data layout of dataset '{}': {} (corrupt file?)", name, error.reason));
  }
}

void h5CheckChunkValueSize(const std::string& path, hid_t dataset, const std::string& name,
                           std::size_t type_size) {
  const uint64_t declared = h5ChunkValueSize(path, dataset, name);
  if (declared != 0 && declared != type_size) {
    throw InputError(
        path, fmt::format("dataset '{}' holds values of {} bytes but its chunk layout declares values of "
                          "{} bytes (corrupt layout message?)",
                          name, type_size, declared));
  }
}

}  // namespace asynevo::io_detail
