// Prophesee RAW (EVT 3.0, EVT 2.0) and DAT readers. Every bit layout below is taken from Prophesee's
// public documentation ("RAW File Format", "EVT 3.0 Format", "EVT 2.0 Format", "DAT File Format",
// https://docs.prophesee.ai/stable/data/); see prophesee_reader.hpp for the addresses.
#include "prophesee_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <tuple>

#include "asynevo/core/error.hpp"
#include "little_endian.hpp"
#include "event_extent.hpp"

namespace asynevo::io_detail {

namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 20;       // bytes read per fread
constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;   // a real header is < 1 KiB
constexpr int kEvtLimit = 2048;     // EVT 2.0/3.0: "sensors with up to 2048x2048 resolution" (11-bit x, y)
constexpr int kDatLimit = 16384;    // DAT: 14-bit x and y fields

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool equalsIgnoreCase(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

bool startsWithIgnoreCase(const std::string& text, const std::string& prefix) {
  return text.size() >= prefix.size() && equalsIgnoreCase(text.substr(0, prefix.size()), prefix);
}

std::string toLower(std::string s) {
  for (char& c : s) c = lower(c);
  return s;
}

// Header text: printable ASCII, tab, carriage return, and bytes >= 0x80 (UTF-8 in names or paths).
// Any other control byte means the "% " that started the line was binary data, not a header line.
bool isHeaderByte(unsigned char c) { return c >= 0x20 ? c != 0x7F : (c == '\t' || c == '\r'); }

// A whole non-negative decimal number of at most 9 digits; -1 otherwise.
int parseSize(const std::string& text) {
  if (text.empty() || text.size() > 9) return -1;
  int value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return -1;
    value = value * 10 + (c - '0');
  }
  return value;
}


std::string formatLabel(const std::string& format) {
  if (format == "evt3") return "EVT 3.0";
  if (format == "evt2") return "EVT 2.0";
  return "DAT";
}

// Sensors of Prophesee's own cameras, recognised from the header's plugin_name when the header has no
// size. Only sizes documented for these sensors are listed; anything else falls through to the
// configured size or the events' bounding box.
// `encoding` is the sensor's default encoding ("Data Encoding Formats": Gen3 sensors use EVT 2.0, Gen4
// and IMX636 sensors EVT 3.0), assumed only for legacy headers that have no 'evt' or 'format' line.
struct KnownCamera {
  const char* plugin_part;  // a substring of plugin_name
  int width;
  int height;
  const char* encoding;
};
constexpr KnownCamera kKnownCameras[] = {
    {"imx636", 1280, 720, "evt3"},  // IMX636 (EVK4): HD
    {"gen41", 1280, 720, "evt3"},   // Gen4.1 (EVK3 HD)
    {"gen4_", 1280, 720, "evt3"},   // Gen4
    {"gen31", 640, 480, "evt2"},    // Gen3.1 VGA
    {"gen3_", 640, 480, "evt2"},    // Gen3 VGA (not the Gen3 ATIS, which is excluded below)
    {"genx320", 320, 320, ""},      // GenX320 (its default encoding, EVT 2.1, is not decoded here)
};

const KnownCamera* knownCamera(const PropheseeHeader& header) {
  const PropheseeHeaderLine* plugin = header.find("plugin_name");
  if (plugin == nullptr) return nullptr;
  const std::string name = toLower(plugin->value);
  if (name.find("atis") != std::string::npos) return nullptr;
  for (const KnownCamera& camera : kKnownCameras) {
    if (name.find(camera.plugin_part) != std::string::npos) return &camera;
  }
  return nullptr;
}

// The sensor size a header states: "geometry WxH", "format EVTn;height=H;width=W", or "width W" and
// "height H" lines (RAW and DAT spell the last two "width"/"Width"). {0, 0} when it states none.
struct HeaderSize {
  int width = 0;
  int height = 0;
  const PropheseeHeaderLine* line = nullptr;
};

HeaderSize headerSize(const PropheseeHeader& header, const std::string& path, int limit) {
  HeaderSize size;
  if (const PropheseeHeaderLine* geometry = header.find("geometry")) {
    const std::size_t x = geometry->value.find('x');
    if (x != std::string::npos) {
      size.width = parseSize(geometry->value.substr(0, x));
      size.height = parseSize(geometry->value.substr(x + 1));
    }
    if (x == std::string::npos || size.width < 0 || size.height < 0)
      throw InputError::atByte(path, geometry->offset, "header line '" + geometry->text + "' is not 'geometry WxH'");
    size.line = geometry;
  } else if (const PropheseeHeaderLine* format = header.find("format");
             format != nullptr && format->value.find('=') != std::string::npos) {
    std::size_t start = format->value.find(';');
    while (start != std::string::npos) {
      const std::size_t next = format->value.find(';', start + 1);
      const std::string field = format->value.substr(start + 1, next == std::string::npos ? next : next - start - 1);
      const std::size_t eq = field.find('=');
      if (eq != std::string::npos) {
        const std::string key = toLower(field.substr(0, eq));
        if (key == "width") size.width = parseSize(field.substr(eq + 1));
        if (key == "height") size.height = parseSize(field.substr(eq + 1));
      }
      start = next;
    }
    if (size.width < 0 || size.height < 0)
      throw InputError::atByte(path, format->offset, "header line '" + format->text + "' has a width or height that is not a number");
    if ((size.width > 0) != (size.height > 0))
      throw InputError::atByte(path, format->offset, "header line '" + format->text + "' gives only one of width and height");
    if (size.width > 0) size.line = format;
  }
  if (size.line == nullptr) {
    const PropheseeHeaderLine* width = header.find("width");
    const PropheseeHeaderLine* height = header.find("height");
    if ((width == nullptr) != (height == nullptr)) {
      const PropheseeHeaderLine* one = width != nullptr ? width : height;
      throw InputError::atByte(path, one->offset, "the header gives '" + one->text + "' but not the other sensor dimension");
    }
    if (width != nullptr) {
      size.width = parseSize(width->value);
      size.height = parseSize(height->value);
      size.line = size.width < 0 ? width : height;
      if (size.width < 0 || size.height < 0)
        throw InputError::atByte(path, size.line->offset, "header line '" + size.line->text + "' is not a whole number");
    }
  }
  if (size.line != nullptr && (size.width < 1 || size.height < 1 || size.width > limit || size.height > limit)) {
    throw InputError::atByte(path, size.line->offset,
                             fmt::format("sensor size {}x{} in the header is outside 1..{}", size.width, size.height, limit));
  }
  return size;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Header

const PropheseeHeaderLine* PropheseeHeader::find(const std::string& keyword) const {
  for (const PropheseeHeaderLine& line : lines) {
    if (equalsIgnoreCase(line.keyword, keyword)) return &line;
  }
  return nullptr;
}

PropheseeHeader readPropheseeHeader(std::FILE* file, const std::string& path) {
  PropheseeHeader header;
  if (std::fseek(file, 0, SEEK_SET) != 0) throw InputError(path, "cannot seek to the start of the file");
  std::string text;
  bool eof = false;
  const auto more = [&]() {  // appends a block of the file to `text`; false at the end of the file
    if (eof) return false;
    if (text.size() >= kMaxHeaderBytes)
      throw InputError::atByte(path, text.size(), "the '%' header is longer than 1 MiB; not a Prophesee file?");
    char block[4096];
    const std::size_t got = std::fread(block, 1, sizeof(block), file);
    if (got == 0) {
      if (std::ferror(file)) throw InputError(path, std::string("read error: ") + std::strerror(errno));
      eof = true;
      return false;
    }
    text.append(block, got);
    return true;
  };
  std::size_t pos = 0;
  for (;;) {
    while (text.size() < pos + 2 && more()) {
    }
    if (text.size() < pos + 2 || text[pos] != '%' || text[pos + 1] != ' ') break;  // data starts here
    std::size_t end = pos + 2;
    bool binary = false;
    for (;;) {
      while (end < text.size() && text[end] != '\n' && isHeaderByte(static_cast<unsigned char>(text[end]))) ++end;
      if (end < text.size()) {
        binary = text[end] != '\n';
        break;
      }
      if (!more()) {
        throw InputError::atByte(path, pos, "truncated: the file ends inside its '%' header, in a line without a line end");
      }
    }
    if (binary) break;  // "% " followed by control bytes: event data, not a header line
    PropheseeHeaderLine line;
    line.offset = pos;
    line.text = text.substr(pos + 2, end - pos - 2);
    while (!line.text.empty() && (line.text.back() == '\r' || line.text.back() == ' ' || line.text.back() == '\t'))
      line.text.pop_back();
    const std::size_t space = line.text.find(' ');
    line.keyword = line.text.substr(0, space);
    if (space != std::string::npos) {
      line.value = line.text.substr(line.text.find_first_not_of(' ', space));
    }
    header.lines.push_back(line);
    pos = end + 1;
    if (equalsIgnoreCase(line.keyword, "end") && line.value.empty()) break;  // "% end" closes the header
  }
  header.data_offset = pos;
  return header;
}

std::string propheseeFormatFromHeader(const PropheseeHeader& header, const std::string& path) {
  std::string from_evt;
  std::string from_format;
  const PropheseeHeaderLine* evt = header.find("evt");
  if (evt != nullptr) {
    if (evt->value == "3.0" || evt->value == "3") {
      from_evt = "evt3";
    } else if (evt->value == "2.0" || evt->value == "2") {
      from_evt = "evt2";
    } else {
      throw InputError::atByte(path, evt->offset,
                               "the header names the encoding 'evt " + evt->value +
                                   "', which AsynEVO does not decode (supported: EVT 3.0, EVT 2.0)");
    }
  }
  const PropheseeHeaderLine* format = header.find("format");
  if (format != nullptr) {
    std::string name = format->value.substr(0, format->value.find(';'));
    for (char& c : name) c = (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
    if (name == "EVT3") {
      from_format = "evt3";
    } else if (name == "EVT2") {
      from_format = "evt2";
    } else {
      throw InputError::atByte(path, format->offset,
                               "the header names the format '" + name +
                                   "', which AsynEVO does not decode (supported: EVT3, EVT2)");
    }
  }
  if (!from_evt.empty() && !from_format.empty() && from_evt != from_format) {
    throw InputError::atByte(path, format->offset,
                             "the header's 'evt " + evt->value + "' and 'format " + format->value + "' lines disagree");
  }
  if (!from_format.empty()) return from_format;
  if (!from_evt.empty()) return from_evt;
  for (const PropheseeHeaderLine& line : header.lines) {
    if (startsWithIgnoreCase(line.text, "Data file containing")) return "dat";
  }
  if (header.find("plugin_name") == nullptr && header.find("Version") != nullptr) return "dat";
  // Legacy RAW headers without 'evt' or 'format': the known camera's default encoding.
  if (const KnownCamera* camera = knownCamera(header)) return camera->encoding;
  return "";
}

// ---------------------------------------------------------------------------------------------------
// Common reader part

PropheseeReader::PropheseeReader(const std::string& path, const ReaderOptions& options, const char* format,
                                 int word_bytes)
    : options_(options), file_(openFile(path, "rb")), chunk_(readBufferBytes(path, kChunkBytes)), word_bytes_(word_bytes),
      format_label_(formatLabel(format)) {
  if (!file_) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  info_.path = path;
  info_.format = format;
  header_ = readPropheseeHeader(file_.get(), path);
  const std::string named = propheseeFormatFromHeader(header_, path);
  if (!named.empty() && named != info_.format) {
    throw InputError::atByte(path, 0,
                             "the header names the format " + formatLabel(named) + ", not " + format_label_ +
                                 " (read it with --format " + named + " or auto)");
  }
}

void PropheseeReader::fail(uint64_t offset, const std::string& message) const {
  throw InputError::atByte(info_.path, offset, message);
}

void PropheseeReader::startData(uint64_t data_offset, int limit) {
  data_offset_ = data_offset;
  const HeaderSize stated = headerSize(header_, info_.path, limit);
  const bool configured = options_.width > 0 && options_.height > 0;
  int width = 0;
  int height = 0;
  bool settable = true;  // whether the out-of-sensor error says how to set another size
  if (stated.line != nullptr) {
    // The header is the recording's own statement: another size given for it is a mistake, not an override.
    if (configured && (options_.width != stated.width || options_.height != stated.height)) {
      throw InputError::atByte(
          info_.path, stated.line->offset,
          fmt::format("sensor size {}x{} in the header differs from {}x{} set by {} (the file's own size is kept "
                      "only when they agree: correct or drop that setting)",
                      stated.width, stated.height, options_.width, options_.height, options_.size_origin));
    }
    width = stated.width;
    height = stated.height;
    info_.size_origin = "the file's header";
    settable = false;
  } else if (configured) {
    width = options_.width;
    height = options_.height;
    info_.size_origin = options_.size_origin;
  } else if (const KnownCamera* camera = knownCamera(header_)) {
    width = camera->width;
    height = camera->height;
    info_.size_origin = "the camera the header names";
  } else {
    info_.size_origin = "the events' extent, the header states no size";
    // No size anywhere: one pass over the events to find their bounding box (still in bounded memory).
    checker_ = EventChecker(limit, limit, options_.max_time_reversal_ns);
    if (std::fseek(file_.get(), static_cast<long>(data_offset_), SEEK_SET) != 0)
      throw InputError(info_.path, "cannot seek to the event data");
    chunk_offset_ = data_offset_;
    resetDecoder();
    std::tie(width, height) = extentOfEvents(*this);
  }
  info_.width = width;
  info_.height = height;
  checker_ = EventChecker(width, height, options_.max_time_reversal_ns, info_.size_origin, settable);
  if (std::fseek(file_.get(), static_cast<long>(data_offset_), SEEK_SET) != 0)
    throw InputError(info_.path, "cannot seek to the event data");
  pos_ = end_ = filled_ = 0;
  chunk_offset_ = data_offset_;
  eof_ = false;
  stats_ = ReaderStats{};
  resetDecoder();
}

bool PropheseeReader::nextChunk() {
  // Keep the bytes not yet decoded (at most a partial word) and fill the rest of the chunk.
  const std::size_t kept = filled_ - pos_;
  std::memmove(chunk_.data(), chunk_.data() + pos_, kept);
  chunk_offset_ += pos_;
  pos_ = 0;
  filled_ = kept;
  while (!eof_ && filled_ < chunk_.size()) {
    const std::size_t got = std::fread(chunk_.data() + filled_, 1, chunk_.size() - filled_, file_.get());
    if (got == 0) {
      if (std::ferror(file_.get())) throw InputError(info_.path, std::string("read error: ") + std::strerror(errno));
      eof_ = true;
    }
    filled_ += got;
  }
  end_ = filled_ - filled_ % static_cast<std::size_t>(word_bytes_);
  if (end_ == 0 && filled_ > 0) {
    fail(chunk_offset_, fmt::format("truncated: the last {} {} has only {} of its {} bytes", format_label_,
                                    word_bytes_ == 8 ? "event record" : "word", filled_, word_bytes_));
  }
  return end_ > 0;
}

bool PropheseeReader::read(EventPacket& packet) {
  packet.first_index = stats_.events;
  const auto capacity = static_cast<std::size_t>(options_.packet_size);
  if (packet.events.size() != capacity) packet.events.resize(capacity);
  const std::size_t n = decode(packet.events.data(), capacity);
  packet.events.resize(n);
  stats_.events += n;
  stats_.clamped_times = checker_.clamped();
  return n > 0;
}

// ---------------------------------------------------------------------------------------------------
// EVT 3.0. Word = 16 bits, little-endian; bits 15..12 are the type:
//   0000 EVT_ADDR_Y   bit 11 system type (master/slave), bits 10..0 y
//   0010 EVT_ADDR_X   bit 11 polarity, bits 10..0 x: one event at (x, y) and the current time
//   0011 VECT_BASE_X  bit 11 polarity, bits 10..0 x: base of the following vector words
//   0100 VECT_12      bits 11..0: bit i set = an event at base x + i; then base x += 12
//   0101 VECT_8       bits 7..0: as VECT_12 with 8 elements; then base x += 8
//   0110 EVT_TIME_LOW bits 11..0 = the low 12 bits of the 24-bit µs time base
//   0111 CONTINUED_4, 1111 CONTINUED_12, 1110 OTHERS: extension data (skipped, counted)
//   1000 EVT_TIME_HIGH bits 11..0 = the high 12 bits of the 24-bit time base
//   1010 EXT_TRIGGER  bits 11..8 channel, bit 0 edge (counted, not delivered)
// Other types are reserved. The 24-bit time base wraps every 2^24 µs (16.8 s): a TIME_HIGH more than
// half its range below the previous one is a wrap and extends the time to 64 bits. TIME_LOW never
// wraps by itself (a TIME_HIGH always follows its overflow), so its decreases are not counted as wraps.

Evt3Reader::Evt3Reader(const std::string& path, const ReaderOptions& options)
    : PropheseeReader(path, options, "evt3", 2) {
  startData(header_.data_offset, kEvtLimit);
}

std::size_t Evt3Reader::decode(Event* out, std::size_t capacity) {
  try {
    // The first call only delivers the rest of a vector the last packet could not hold.
    std::size_t n = decoder_.decode(chunk_.data(), pos_, pos_, chunk_offset_, out, 0, capacity, checker_, stats_);
    while (n < capacity) {
      if (pos_ == end_ && !nextChunk()) break;
      n = decoder_.decode(chunk_.data(), pos_, end_, chunk_offset_, out, n, capacity, checker_, stats_);
    }
    return n;
  } catch (const EvtDecodeError& e) {
    fail(e.offset, e.message);
  }
}

// ---------------------------------------------------------------------------------------------------
// EVT 2.0. Word = 32 bits, little-endian; bits 31..28 are the type:
//   0000 CD_OFF, 0001 CD_ON  bits 27..22 time bits 5..0, bits 21..11 x, bits 10..0 y
//   1000 EVT_TIME_HIGH       bits 27..0 = time bits 33..6
//   1010 EXT_TRIGGER         bits 27..22 time, bits 12..8 channel, bit 0 edge (counted, not delivered)
//   1110 OTHERS, 1111 CONTINUED: extension data (skipped, counted)
// Other types are reserved. The 34-bit µs time wraps every 2^34 µs (4 h 46 min); a TIME_HIGH more than
// half its range below the previous one is a wrap.

Evt2Reader::Evt2Reader(const std::string& path, const ReaderOptions& options)
    : PropheseeReader(path, options, "evt2", 4) {
  startData(header_.data_offset, kEvtLimit);
}

std::size_t Evt2Reader::decode(Event* out, std::size_t capacity) {
  try {
    std::size_t n = 0;
    while (n < capacity) {
      if (pos_ == end_ && !nextChunk()) break;
      n = decoder_.decode(chunk_.data(), pos_, end_, chunk_offset_, out, n, capacity, checker_, stats_);
    }
    return n;
  } catch (const EvtDecodeError& e) {
    fail(e.offset, e.message);
  }
}

// ---------------------------------------------------------------------------------------------------
// DAT. After the header: one byte event type (0x00 Event2d, 0x0C EventCd, 0x0E EventExtTrigger) and one
// byte event size (8). Then 8-byte little-endian records: uint32 time in µs, then uint32 with x in bits
// 0..13, y in bits 14..27 and polarity in bits 28..31. The 32-bit time wraps every 2^32 µs (71.6 min); a
// time more than half that range below the previous one is taken as a wrap.

DatReader::DatReader(const std::string& path, const ReaderOptions& options)
    : PropheseeReader(path, options, "dat", 8) {
  const uint64_t at = header_.data_offset;
  unsigned char type_size[2];
  if (std::fseek(file_.get(), static_cast<long>(at), SEEK_SET) != 0 ||
      std::fread(type_size, 1, 2, file_.get()) != 2) {
    throw InputError::atByte(path, at, "truncated: no event type and size bytes after the DAT header");
  }
  if (type_size[0] == 0x0E)
    throw InputError::atByte(path, at, "this DAT file holds external-trigger events (type 0x0E), not CD events");
  if (type_size[0] != 0x00 && type_size[0] != 0x0C) {
    throw InputError::atByte(path, at, fmt::format("unknown DAT event type 0x{:02X} (expected 0x00 Event2d or 0x0C "
                                                   "EventCd); not a DAT file of CD events?",
                                                   type_size[0]));
  }
  if (type_size[1] != 8)
    throw InputError::atByte(path, at + 1, fmt::format("DAT event size {} bytes, expected 8", type_size[1]));
  startData(at + 2, kDatLimit);
}

void DatReader::resetDecoder() {
  wraps_ = 0;
  last_raw_t_ = 0;
  have_time_ = false;
}

std::size_t DatReader::decode(Event* out, std::size_t capacity) {
  std::size_t n = 0;
  while (n < capacity) {
    if (pos_ == end_ && !nextChunk()) break;
    const unsigned char* p = chunk_.data() + pos_;
    const uint32_t t = load32(p);
    const uint32_t data = load32(p + 4);
    pos_ += 8;
    if (have_time_ && t < last_raw_t_ && last_raw_t_ - t > 0x80000000u) ++wraps_;
    last_raw_t_ = t;
    have_time_ = true;
    emit(out[n], usToNs((wraps_ << 32) | t, offsetOf(pos_ - 8)), data & 0x3FFF, (data >> 14) & 0x3FFF, data >> 28,
         offsetOf(pos_ - 8));
    ++n;
  }
  return n;
}

}  // namespace asynevo::io_detail
