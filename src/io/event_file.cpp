#include "asynevo/io/event_file.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <vector>

#include "asynevo/core/error.hpp"
#include "event_file_reader.hpp"

namespace asynevo {

namespace {

template <class T>
void put(unsigned char*& p, T value) {
  std::memcpy(p, &value, sizeof(T));  // x86-64 and aarch64 are little-endian, as the format
  p += sizeof(T);
}

template <class T>
T get(const unsigned char*& p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  p += sizeof(T);
  return value;
}

}  // namespace

EventFileWriter::EventFileWriter(const std::string& path, int width, int height)
    : path_(path), file_(openFile(path, "wb")), width_(width), height_(height) {
  if (!file_) throw InputError(path, std::string("cannot create event file: ") + std::strerror(errno));
  writeHeader();
}

EventFileWriter::~EventFileWriter() {
  if (!file_) return;
  try {
    close();
  } catch (const std::exception&) {  // NOLINT(bugprone-empty-catch): destructors must not throw
  }
}

void EventFileWriter::writeHeader() {
  unsigned char header[kEventFileHeaderBytes] = {};
  unsigned char* p = header;
  std::memcpy(p, kEventFileMagic, sizeof(kEventFileMagic));
  p += sizeof(kEventFileMagic);
  put<uint32_t>(p, 1);
  put<uint32_t>(p, static_cast<uint32_t>(width_));
  put<uint32_t>(p, static_cast<uint32_t>(height_));
  put<uint32_t>(p, static_cast<uint32_t>(kEventFileRecordBytes));
  put<uint64_t>(p, count_);
  put<int64_t>(p, first_t_ns_);
  put<int64_t>(p, last_t_ns_);
  if (std::fseek(file_.get(), 0, SEEK_SET) != 0 || std::fwrite(header, 1, sizeof(header), file_.get()) != sizeof(header))
    throw InputError(path_, "cannot write event file header");
}

void EventFileWriter::write(const Event* events, std::size_t count) {
  if (count == 0) return;
  std::vector<unsigned char> records(count * kEventFileRecordBytes, 0);
  unsigned char* p = records.data();
  for (std::size_t i = 0; i < count; ++i) {
    unsigned char* record = p + i * kEventFileRecordBytes;
    put<int64_t>(record, events[i].t_ns);
    put<uint16_t>(record, events[i].x);
    put<uint16_t>(record, events[i].y);
    put<int8_t>(record, events[i].polarity);
  }
  if (std::fwrite(records.data(), 1, records.size(), file_.get()) != records.size())
    throw InputError(path_, "cannot write events (disk full?)");
  if (count_ == 0) first_t_ns_ = events[0].t_ns;
  last_t_ns_ = events[count - 1].t_ns;
  count_ += count;
}

void EventFileWriter::close() {
  if (!file_) return;
  writeHeader();
  const bool ok = std::fflush(file_.get()) == 0;
  file_.reset();
  if (!ok) throw InputError(path_, "cannot finish event file");
}

namespace io_detail {

EventFileReader::EventFileReader(const std::string& path, const ReaderOptions& options)
    : file_(openFile(path, "rb")), packet_size_(options.packet_size), checker_(1, 1, 0) {
  if (!file_) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  info_.path = path;
  info_.format = "aevt";
  unsigned char header[kEventFileHeaderBytes];
  if (std::fread(header, 1, sizeof(header), file_.get()) != sizeof(header))
    throw InputError(path, "truncated .aevt header (fewer than 64 bytes)");
  const unsigned char* p = header;
  if (std::memcmp(p, kEventFileMagic, sizeof(kEventFileMagic)) != 0) throw InputError(path, "not an .aevt file");
  p += sizeof(kEventFileMagic);
  const auto version = get<uint32_t>(p);
  info_.width = static_cast<int>(get<uint32_t>(p));
  info_.height = static_cast<int>(get<uint32_t>(p));
  const auto record_bytes = get<uint32_t>(p);
  count_ = get<uint64_t>(p);
  if (version != 1) throw InputError(path, "unsupported .aevt version " + std::to_string(version));
  if (record_bytes != kEventFileRecordBytes) throw InputError(path, "unsupported .aevt record size");
  if (info_.width <= 0 || info_.height <= 0 || info_.width > 65535 || info_.height > 65535)
    throw InputError(path, "invalid sensor size in .aevt header");
  if ((options.width > 0 && options.width != info_.width) || (options.height > 0 && options.height != info_.height)) {
    throw InputError(path, "sensor size " + std::to_string(info_.width) + "x" + std::to_string(info_.height) +
                               " in the .aevt header differs from " + std::to_string(options.width) + "x" +
                               std::to_string(options.height) + " set by " + options.size_origin +
                               " (the file's own size is kept only when they agree: correct or drop that setting)");
  }
  info_.size_origin = "the .aevt header";
  std::fseek(file_.get(), 0, SEEK_END);
  const long size = std::ftell(file_.get());
  std::fseek(file_.get(), static_cast<long>(kEventFileHeaderBytes), SEEK_SET);
  // A count whose byte size does not fit in 64 bits would wrap around and could match the file's size.
  const uint64_t max_count = (UINT64_MAX - kEventFileHeaderBytes) / kEventFileRecordBytes;
  if (count_ > max_count) {
    throw InputError(path, "corrupt .aevt file: the header announces " + std::to_string(count_) +
                               " events, more than any file can hold");
  }
  const uint64_t expected = kEventFileHeaderBytes + count_ * kEventFileRecordBytes;
  if (size < 0 || static_cast<uint64_t>(size) != expected) {
    throw InputError(path, "truncated or corrupt .aevt file: the header announces " + std::to_string(count_) +
                               " events (" + std::to_string(expected) + " bytes) but the file has " +
                               std::to_string(size) + " bytes");
  }
  checker_ = EventChecker(info_.width, info_.height, options.max_time_reversal_ns, info_.size_origin);
}

bool EventFileReader::read(EventPacket& packet) {
  packet.events.clear();
  packet.first_index = stats_.events;
  const uint64_t left = count_ - stats_.events;
  const std::size_t n = static_cast<std::size_t>(std::min<uint64_t>(left, static_cast<uint64_t>(packet_size_)));
  if (n == 0) return false;
  bytes_.resize(n * kEventFileRecordBytes);
  if (std::fread(bytes_.data(), 1, bytes_.size(), file_.get()) != bytes_.size())
    throw InputError::atRecord(info_.path, stats_.events, "read error (file changed while reading?)");
  packet.events.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* record = bytes_.data() + i * kEventFileRecordBytes;
    const auto t_ns = get<int64_t>(record);
    const auto x = get<uint16_t>(record);
    const auto y = get<uint16_t>(record);
    const auto polarity = get<int8_t>(record);
    if (!checker_.accept(t_ns, x, y, polarity, packet.events[i], error_))
      throw InputError::atRecord(info_.path, stats_.events + i, error_);
  }
  stats_.events += n;
  stats_.clamped_times = checker_.clamped();
  return true;
}

}  // namespace io_detail

}  // namespace asynevo
