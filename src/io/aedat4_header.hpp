#pragma once
// The start of an AEDAT 4.0 file (iniVation DV): the version line "#!AER-DAT4.0\r\n", an int32 size and
// an IOHeader FlatBuffer of that size with the packets' compression, the position of the data table at
// the end of the file (or -1) and an XML "info node" that lists the streams. Specification:
// https://docs.inivation.com/software/software-advanced-usage/file-formats/aedat-4.0.html
// Reader: aedat4_reader.hpp; format notes: docs/reference/formats_aedat4.md.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace asynevo::io_detail::aedat4 {

constexpr char kMagic[] = "#!AER-DAT4.0\r\n";
constexpr std::size_t kMagicBytes = sizeof(kMagic) - 1;  // 14
/// "#!AER-DAT" starts every AEDAT version line (1.0 has none; 2.0, 3.x and 4.0 have one).
constexpr char kVersionPrefix[] = "#!AER-DAT";

/// IOHeader.compression (enum CompressionType : int32), the same for every packet of the file.
enum class Compression : int32_t { kNone = 0, kLz4 = 1, kLz4High = 2, kZstd = 3, kZstdHigh = 4 };

/// "none", "LZ4", "LZ4 high", "Zstd", "Zstd high"; "" for other values.
const char* compressionName(int32_t compression);

/// One stream the info node lists: <node name="ID"> under "outInfo", with the attributes typeIdentifier,
/// originalOutputName and, in its "info" child, sizeX and sizeY.
struct Stream {
  int id = 0;
  std::string type;   ///< typeIdentifier: "EVTS", "FRME", "IMUS", "TRIG", ...; "" when missing
  std::string name;   ///< originalOutputName; may be empty
  int width = 0;      ///< sizeX, 0 when missing
  int height = 0;     ///< sizeY, 0 when missing
};

struct Header {
  Compression compression = Compression::kNone;
  int64_t data_table_position = -1;  ///< byte offset of the FileDataTable, -1 when the file has none
  uint64_t data_offset = 0;          ///< byte offset of the first packet
  std::vector<Stream> streams;       ///< by increasing id
};

/// Reads and checks the header of `file` (from its start). Throws InputError naming `path` and the byte
/// offset on a wrong version line, a truncated or corrupt IOHeader, an unknown compression or an info node
/// that is not the expected XML.
Header readHeader(std::FILE* file, const std::string& path);

/// The streams of an info node. `xml_offset` is the byte offset of the XML text in the file, for messages.
/// Throws InputError on unterminated tags, unknown entities, stream node names that are not ids or sizes
/// out of range.
std::vector<Stream> parseStreams(const std::string& xml, const std::string& path, uint64_t xml_offset);

}  // namespace asynevo::io_detail::aedat4
