#pragma once
// AEDAT 4.0 files built byte by byte in the tests from iniVation's published specification
// (https://docs.inivation.com/software/software-advanced-usage/file-formats/aedat-4.0.html and the
// FlatBuffer schemas io_header.fbs, events.fbs, imu.fbs), not with any AsynEVO writer. FlatBuffers are laid
// out by hand, front to back, as DV lays them out: size prefix, root offset, file identifier, vtable, table,
// then the referenced vector or string, with 8-byte fields aligned relative to the size prefix. Packets are
// compressed with the formats' own libraries (liblz4 frames, libzstd frames), as the specification says.

#include <lz4frame.h>
#include <zstd.h>

#include <cstdint>
#include <string>
#include <vector>

namespace asynevo::testing::aedat4 {

inline std::string le16(uint32_t v) { return {static_cast<char>(v & 0xFF), static_cast<char>((v >> 8) & 0xFF)}; }
inline std::string le32(uint32_t v) { return le16(v & 0xFFFF) + le16(v >> 16); }
inline std::string le64(uint64_t v) { return le32(static_cast<uint32_t>(v)) + le32(static_cast<uint32_t>(v >> 32)); }

inline const std::string kMagic = "#!AER-DAT4.0\r\n";

/// IOHeader: compression (int32, field 0), dataTablePosition (int64, field 1), infoNode (string, field 2).
/// Returned with its size prefix, i.e. exactly the bytes that follow the version line.
inline std::string ioHeader(int32_t compression, int64_t data_table_position, const std::string& xml) {
  std::string b = le32(0);                    // 0: size prefix (filled below)
  b += le32(24 - 4);                          // 4: root offset -> table at 24
  b += "IOHE";                                // 8: file identifier
  b += le16(10) + le16(20) + le16(4) + le16(8) + le16(16);  // 12: vtable (size, table size, 3 field offsets)
  b += le16(0);                               // 22: padding
  b += le32(24 - 12);                         // 24: table: soffset to the vtable at 12
  b += le32(static_cast<uint32_t>(compression));            // 28: compression
  b += le64(static_cast<uint64_t>(data_table_position));    // 32: dataTablePosition
  b += le32(44 - 40);                         // 40: offset to the string at 44
  b += le32(static_cast<uint32_t>(xml.size())) + xml + std::string(1, '\0');
  while (b.size() % 4 != 0) b += '\0';
  const std::string size = le32(static_cast<uint32_t>(b.size() - 4));
  return b.replace(0, 4, size);
}

/// One stream of the info node.
struct StreamSpec {
  int id;
  const char* type;  // typeIdentifier
  const char* name;  // originalOutputName
  int width = 0;     // sizeX/sizeY; 0 = not given
  int height = 0;
};

/// The info node XML as DV writes it: <dv><node name="outInfo"><node name="ID">attributes<node name="info">.
inline std::string infoXml(const std::vector<StreamSpec>& streams) {
  std::string xml = "<dv version=\"2.0\">\n    <node name=\"outInfo\" path=\"/mainloop/Recorder/outInfo/\">\n";
  for (const StreamSpec& s : streams) {
    const std::string id = std::to_string(s.id);
    xml += "        <node name=\"" + id + "\" path=\"/mainloop/Recorder/outInfo/" + id + "/\">\n";
    xml += "            <attr key=\"compression\" type=\"string\">LZ4</attr>\n";
    xml += std::string("            <attr key=\"originalOutputName\" type=\"string\">") + s.name + "</attr>\n";
    xml += "            <attr key=\"typeDescription\" type=\"string\">A &quot;test&quot; stream &amp; more.</attr>\n";
    xml += std::string("            <attr key=\"typeIdentifier\" type=\"string\">") + s.type + "</attr>\n";
    xml += "            <node name=\"info\" path=\"/mainloop/Recorder/outInfo/" + id + "/info/\">\n";
    if (s.width > 0) xml += "                <attr key=\"sizeX\" type=\"int\">" + std::to_string(s.width) + "</attr>\n";
    if (s.height > 0) xml += "                <attr key=\"sizeY\" type=\"int\">" + std::to_string(s.height) + "</attr>\n";
    xml += "                <attr key=\"source\" type=\"string\">TestCamera_0001</attr>\n";
    xml += "            </node>\n        </node>\n";
  }
  return xml + "    </node>\n</dv>\n";
}

/// An event of the EventPacket vector: struct Event { int64 timestamp (µs); int16 x; int16 y; bool polarity }.
struct RawEvent {
  int64_t t_us;
  int x;
  int y;
  int on;
};

/// A size-prefixed EventPacket FlatBuffer (identifier "EVTS"): its vector of 16-byte Event structs.
inline std::string eventPacket(const std::vector<RawEvent>& events) {
  std::string b = le32(0) + le32(20 - 4) + "EVTS";   // 0: size prefix, 4: root offset -> table at 20, 8: identifier
  b += le16(6) + le16(8) + le16(4) + le16(0);        // 12: vtable (size 6, table size 8, field 0 at +4), padding
  b += le32(20 - 12);                                // 20: table: soffset to the vtable at 12
  b += le32(28 - 24);                                // 24: offset to the vector at 28
  b += le32(static_cast<uint32_t>(events.size()));   // 28: vector length; elements from 32 (8-byte aligned)
  for (const RawEvent& e : events) {
    b += le64(static_cast<uint64_t>(e.t_us)) + le16(static_cast<uint32_t>(e.x)) + le16(static_cast<uint32_t>(e.y));
    b += std::string(1, static_cast<char>(e.on)) + std::string(3, '\0');
  }
  return b.replace(0, 4, le32(static_cast<uint32_t>(b.size() - 4)));
}

/// A size-prefixed IMUPacket FlatBuffer (identifier "IMUS") with `count` IMU tables, all of them one
/// table that holds only a timestamp (the other IMU fields are optional).
inline std::string imuPacket(uint32_t count, int64_t t_us) {
  std::string b = le32(0) + le32(20 - 4) + "IMUS";   // 0: size prefix, 4: root -> table at 20, 8: identifier
  b += le16(6) + le16(8) + le16(4) + le16(0);        // 12: IMUPacket vtable, padding
  b += le32(20 - 12);                                // 20: IMUPacket table
  b += le32(28 - 24);                                // 24: offset to the vector at 28
  b += le32(count);                                  // 28: vector of `count` table offsets
  const std::size_t vtable = 32 + 4 * std::size_t{count};  // the IMU tables' vtable, after the offsets
  const std::size_t table = (vtable + 8 + 7) / 8 * 8;       // the IMU table, 8-byte aligned for its int64
  for (uint32_t i = 0; i < count; ++i) b += le32(static_cast<uint32_t>(table - (32 + 4 * i)));
  b += le16(6) + le16(16) + le16(8) + le16(0);       // IMU vtable: table size 16, field 0 (timestamp) at +8
  b.resize(table, '\0');
  b += le32(static_cast<uint32_t>(table - vtable)) + le32(0) + le64(static_cast<uint64_t>(t_us));
  return b.replace(0, 4, le32(static_cast<uint32_t>(b.size() - 4)));
}

/// Compression types of the IOHeader.
enum Compression : int32_t { kNone = 0, kLz4 = 1, kLz4High = 2, kZstd = 3, kZstdHigh = 4 };

/// One LZ4 frame (LZ4 and LZ4 high differ only in the compressor's effort) or one Zstd frame.
inline std::string compress(const std::string& data, int32_t compression) {
  std::string out;
  if (compression == kLz4 || compression == kLz4High) {
    LZ4F_preferences_t prefs{};
    prefs.compressionLevel = compression == kLz4High ? 9 : 0;
    out.resize(LZ4F_compressFrameBound(data.size(), &prefs));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), &prefs);
    out.resize(LZ4F_isError(n) ? 0 : n);
  } else if (compression == kZstd || compression == kZstdHigh) {
    out.resize(ZSTD_compressBound(data.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), data.data(), data.size(), compression == kZstdHigh ? 19 : 3);
    out.resize(ZSTD_isError(n) ? 0 : n);
  } else {
    out = data;
  }
  return out;
}

/// A packet: PacketHeader { int32 streamID; int32 size } and the payload as given.
inline std::string packet(int32_t stream, const std::string& payload) {
  return le32(static_cast<uint32_t>(stream)) + le32(static_cast<uint32_t>(payload.size())) + payload;
}

}  // namespace asynevo::testing::aedat4
