#include "ecd_text_reader.hpp"

#include <cerrno>
#include <cstring>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::io_detail {

namespace {

constexpr std::size_t kBufferBytes = 1 << 20;  // lines are ~25 bytes; 1 MiB keeps reads large
constexpr int kEcdWidth = 240;                 // DAVIS240C, the ECD sensor
constexpr int kEcdHeight = 180;

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Parses an optionally signed decimal integer; false if the text is anything else.
bool parseInteger(const char* begin, const char* end, int64_t& value) {
  if (begin == end) return false;
  bool negative = false;
  if (*begin == '-' || *begin == '+') {
    negative = *begin == '-';
    ++begin;
  }
  if (begin == end || end - begin > 18) return false;
  int64_t v = 0;
  for (const char* c = begin; c != end; ++c) {
    if (*c < '0' || *c > '9') return false;
    v = v * 10 + (*c - '0');
  }
  value = negative ? -v : v;
  return true;
}

}  // namespace

EcdTextReader::EcdTextReader(const std::string& path, const ReaderOptions& options)
    : file_(openFile(path, "rb")),
      buffer_(readBufferBytes(path, kBufferBytes)),
      packet_size_(options.packet_size),
      checker_(1, 1, 0) {
  if (!file_) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  info_.path = path;
  info_.format = "ecd";
  info_.width = options.width > 0 ? options.width : kEcdWidth;
  info_.height = options.height > 0 ? options.height : kEcdHeight;
  // ECD text stores no size: whatever is in use can be set otherwise, so the out-of-sensor error says how.
  info_.size_origin = options.width > 0 || options.height > 0 ? options.size_origin : "the ECD text default, a DAVIS240C";
  checker_ = EventChecker(info_.width, info_.height, options.max_time_reversal_ns, info_.size_origin, true);
}

void EcdTextReader::fail(const std::string& message) const { throw InputError::atLine(info_.path, line_, message); }

bool EcdTextReader::refill() {
  if (eof_) return false;
  // Move the partial line to the front and read more behind it.
  const std::size_t remaining = end_ - begin_;
  if (remaining == buffer_.size()) {
    line_ += 1;
    fail("line longer than " + std::to_string(buffer_.size()) + " bytes; is this an ECD events.txt?");
  }
  std::memmove(buffer_.data(), buffer_.data() + begin_, remaining);
  begin_ = 0;
  end_ = remaining;
  const std::size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_.get());
  if (got == 0) {
    if (std::ferror(file_.get())) throw InputError(info_.path, "read error: " + std::string(std::strerror(errno)));
    eof_ = true;
  }
  end_ += got;
  return got > 0;
}

bool EcdTextReader::parseLine(const char* begin, const char* end, Event& event) {
  // Split on blanks into at most 5 fields (a 5th means too many).
  const char* field_begin[5];
  const char* field_end[5];
  int fields = 0;
  const char* c = begin;
  while (c != end) {
    while (c != end && isBlank(*c)) ++c;
    if (c == end) break;
    if (fields == 0 && *c == '#') return false;  // comment line
    const char* start = c;
    while (c != end && !isBlank(*c)) ++c;
    if (fields == 5) break;
    field_begin[fields] = start;
    field_end[fields] = c;
    ++fields;
  }
  if (fields == 0) return false;  // blank line
  if (fields != 4) {
    fail("expected 4 fields 't x y p', found " + std::to_string(fields) + (fields == 5 ? " or more" : "") +
         (fields < 4 ? " (truncated line?)" : ""));
  }
  const std::string_view t_text(field_begin[0], static_cast<std::size_t>(field_end[0] - field_begin[0]));
  const std::optional<int64_t> t_ns = parseSecondsToNs(t_text);
  if (!t_ns) fail("time '" + std::string(t_text) + "' is not a finite number of seconds");
  int64_t values[3];
  static constexpr const char* kNames[3] = {"x", "y", "polarity"};
  for (int i = 0; i < 3; ++i) {
    if (!parseInteger(field_begin[i + 1], field_end[i + 1], values[i])) {
      fail(std::string(kNames[i]) + " '" + std::string(field_begin[i + 1], field_end[i + 1]) +
           "' is not an integer");
    }
  }
  if (!checker_.accept(*t_ns, values[0], values[1], values[2], event, error_)) fail(error_);
  return true;
}

bool EcdTextReader::read(EventPacket& packet) {
  packet.events.clear();
  packet.first_index = stats_.events;
  while (static_cast<int>(packet.events.size()) < packet_size_) {
    const char* line_begin = buffer_.data() + begin_;
    const void* newline = std::memchr(line_begin, '\n', end_ - begin_);
    if (newline == nullptr) {
      if (refill()) continue;     // the line continues in the next chunk
      if (begin_ == end_) break;  // end of data
      line_begin = buffer_.data() + begin_;  // refill() moved the last, unterminated line
    }
    const char* line_end = newline ? static_cast<const char*>(newline) : buffer_.data() + end_;
    begin_ = static_cast<std::size_t>(line_end - buffer_.data()) + (newline ? 1 : 0);
    ++line_;
    Event event;
    if (parseLine(line_begin, line_end, event)) {
      packet.events.push_back(event);
    } else {
      ++stats_.skipped_lines;
    }
  }
  stats_.events += packet.events.size();
  stats_.clamped_times = checker_.clamped();
  return !packet.events.empty();
}

}  // namespace asynevo::io_detail
