#include "asynevo/io/event_text.hpp"

#include <fmt/format.h>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo {

namespace {

constexpr std::size_t kFlushBytes = 1 << 20;

char* appendUnsigned(char* p, uint64_t v) {
  char digits[24];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0);
  while (n > 0) *p++ = digits[--n];
  return p;
}

}  // namespace

EventTextWriter::EventTextWriter(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "wb")) {
  if (!file_) throw Error(fmt::format("{}: cannot open file for writing", path));
  buffer_.reserve(kFlushBytes + 64);
}

EventTextWriter::~EventTextWriter() {
  if (file_) std::fclose(file_);
}

void EventTextWriter::write(const Event& e) {
  char line[80];
  char* p = line;
  // The magnitude in unsigned arithmetic, so INT64_MIN does not overflow.
  const uint64_t t = e.t_ns < 0 ? ~static_cast<uint64_t>(e.t_ns) + 1 : static_cast<uint64_t>(e.t_ns);
  if (e.t_ns < 0) *p++ = '-';
  p = appendUnsigned(p, t / static_cast<uint64_t>(kNsPerSecond));
  *p++ = '.';
  uint64_t fraction = t % static_cast<uint64_t>(kNsPerSecond);
  for (int k = 8; k >= 0; --k) {
    p[k] = static_cast<char>('0' + fraction % 10);
    fraction /= 10;
  }
  p += 9;
  *p++ = ' ';
  p = appendUnsigned(p, e.x);
  *p++ = ' ';
  p = appendUnsigned(p, e.y);
  *p++ = ' ';
  *p++ = e.polarity > 0 ? '1' : '0';
  *p++ = '\n';
  buffer_.append(line, static_cast<std::size_t>(p - line));
  if (buffer_.size() >= kFlushBytes) flush();
}

void EventTextWriter::flush() {
  if (buffer_.empty()) return;
  if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
    throw Error(fmt::format("{}: write failed", path_));
  buffer_.clear();
}

void EventTextWriter::close() {
  if (!file_) return;
  flush();
  const bool failed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed) throw Error(fmt::format("{}: write failed", path_));
}

}  // namespace asynevo
