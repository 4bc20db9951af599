// AEDAT 4.0 reader (aedat4_reader.hpp). Packet layout, compression and FlatBuffer schemas from iniVation's
// specification, https://docs.inivation.com/software/software-advanced-usage/file-formats/aedat-4.0.html,
// and the schemas named in aedat4_flatbuffers.hpp.
#include "aedat4_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <tuple>

#include "aedat4_flatbuffers.hpp"
#include "asynevo/core/error.hpp"
#include "event_extent.hpp"

namespace asynevo::io_detail {

namespace {

constexpr std::size_t kMaxPacketBytes = std::size_t{256} << 20;  // compressed or not; real packets are < 1 MiB
constexpr int kCoordinateLimit = 32768;                          // int16 x and y
constexpr int64_t kMaxTimeUs = INT64_MAX / 1000;                 // times are stored in ns

std::string streamList(const std::vector<aedat4::Stream>& streams) {
  std::string list;
  for (const aedat4::Stream& s : streams) {
    list += fmt::format("{}{} {}", list.empty() ? "" : ", ", s.id, s.type.empty() ? "(no type)" : s.type);
  }
  return list.empty() ? "none" : list;
}

}  // namespace

Aedat4Reader::Aedat4Reader(const std::string& path, const ReaderOptions& options)
    : options_(options), file_(openFile(path, "rb")) {
  if (!file_) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  info_.path = path;
  info_.format = "aedat4";
  header_ = aedat4::readHeader(file_.get(), path);
  if (std::fseek(file_.get(), 0, SEEK_END) != 0) throw InputError(path, "cannot seek to the end of the file");
  const auto file_size = static_cast<uint64_t>(std::ftell(file_.get()));
  data_end_ = file_size;
  if (header_.data_table_position >= 0) {
    const auto table = static_cast<uint64_t>(header_.data_table_position);
    if (table > file_size) {
      throw InputError::atByte(path, file_size,
                               fmt::format("truncated: the file ends at byte {}, before the data table the IOHeader "
                                           "places at byte {}",
                                           file_size, table));
    }
    data_end_ = table;
  }
  const auto events = std::find_if(header_.streams.begin(), header_.streams.end(),
                                   [](const aedat4::Stream& s) { return s.type == "EVTS"; });
  if (events == header_.streams.end()) {
    throw InputError::atByte(path, aedat4::kMagicBytes + 4,
                             "no event stream: the IOHeader's info node lists the streams " +
                                 streamList(header_.streams) + ", none with typeIdentifier EVTS");
  }
  event_stream_ = events->id;
  if (header_.compression != aedat4::Compression::kNone)
    decompressor_ = std::make_unique<aedat4::Decompressor>(header_.compression, kMaxPacketBytes);

  // Sensor size: the event stream's sizeX/sizeY, else the configured size, else the events' bounding box.
  const bool stated = events->width > 0 && events->height > 0;
  const bool configured = options_.width > 0 && options_.height > 0;
  if ((events->width > 0) != (events->height > 0)) {
    throw InputError::atByte(path, aedat4::kMagicBytes + 4,
                             fmt::format("the info node gives only one of sizeX and sizeY for event stream {}",
                                         event_stream_));
  }
  if (stated && configured && (options_.width != events->width || options_.height != events->height)) {
    throw InputError::atByte(path, aedat4::kMagicBytes + 4,
                             fmt::format("sensor size {}x{} in the file (event stream {}) differs from {}x{} set "
                                         "by {} (the file's own size is kept only when they agree: correct or "
                                         "drop that setting)",
                                         events->width, events->height, event_stream_, options_.width,
                                         options_.height, options_.size_origin));
  }
  bool settable = true;  // whether the out-of-sensor error says how to set another size
  if (stated) {
    info_.width = events->width;
    info_.height = events->height;
    info_.size_origin = "the file's stream description";
    settable = false;
  } else if (configured) {
    info_.width = options_.width;
    info_.height = options_.height;
    info_.size_origin = options_.size_origin;
  } else {  // one pass over the events to find their bounding box (still one packet at a time)
    checker_ = EventChecker(kCoordinateLimit, kCoordinateLimit, options_.max_time_reversal_ns);
    rewind();
    std::tie(info_.width, info_.height) = extentOfEvents(*this);
    info_.size_origin = "the events' extent, the file states no size";
  }
  checker_ = EventChecker(info_.width, info_.height, options_.max_time_reversal_ns, info_.size_origin, settable);
  rewind();
}

void Aedat4Reader::rewind() {
  if (std::fseek(file_.get(), static_cast<long>(header_.data_offset), SEEK_SET) != 0)
    throw InputError(info_.path, "cannot seek to the first packet");
  next_offset_ = header_.data_offset;
  packet_index_ = packets_seen_ = 0;
  events_ = nullptr;
  event_count_ = next_event_ = 0;
  stats_ = ReaderStats{};
  for (const aedat4::Stream& s : header_.streams) {
    ContainerStream stream;
    stream.id = s.id;
    stream.type = s.type;
    stream.name = s.name;
    stream.width = s.width;
    stream.height = s.height;
    stream.delivered = s.id == event_stream_;
    stats_.streams.push_back(stream);
  }
}

void Aedat4Reader::fail(uint64_t offset, const std::string& message) const {
  throw InputError::atByte(info_.path, offset, message);
}

std::string Aedat4Reader::packetLabel() const {
  for (const ContainerStream& s : stats_.streams) {
    if (s.id == packet_stream_) return fmt::format("packet {} (stream {}, {})", packet_index_, s.id, s.type);
  }
  return fmt::format("packet {} (stream {})", packet_index_, packet_stream_);
}

void Aedat4Reader::decode(uint32_t size) {
  if (!decompressor_) {
    decoded_ = payload_.data();
    decoded_size_ = size;
    return;
  }
  if (!decompressor_->decompress(payload_.data(), size))
    fail(packet_offset_, packetLabel() + ": " + decompressor_->error());
  decoded_ = decompressor_->data();
  decoded_size_ = decompressor_->size();
}

template <class Table>
const uint8_t* Aedat4Reader::elementsOf(const char* what) {
  const char* decompressed = decompressor_ ? "decompressed " : "";
  if (decoded_size_ < 8) {
    fail(packet_offset_, fmt::format("{}: the {}packet has {} bytes, too few for a size-prefixed {} FlatBuffer",
                                     packetLabel(), decompressed, decoded_size_, what));
  }
  const auto prefix = aedat4::loadLe<uint32_t>(decoded_);
  if (prefix != decoded_size_ - 4) {
    fail(packet_offset_, fmt::format("{}: the {} FlatBuffer's size prefix says {} bytes, the {}packet holds {} after it",
                                     packetLabel(), what, prefix, decompressed, decoded_size_ - 4));
  }
  const uint8_t* verified = aedat4::verifySizePrefixed<Table>(decoded_, decoded_size_, scratch_);
  if (verified == nullptr) {
    fail(packet_offset_, fmt::format("{}: the {} FlatBuffer fails verification (an offset or size points outside "
                                     "the packet: corrupt packet)",
                                     packetLabel(), what));
  }
  return flatbuffers::GetSizePrefixedRoot<Table>(verified)->elements();
}

bool Aedat4Reader::nextEventPacket() {
  for (;;) {
    if (next_offset_ == data_end_) return false;
    const char* where = header_.data_table_position >= 0 ? "before the data table" : "at the end of the file";
    packet_offset_ = next_offset_;
    packet_index_ = packets_seen_++;
    const uint64_t left = data_end_ - next_offset_;
    if (left < 8) {
      fail(next_offset_, fmt::format("truncated: the {} bytes {} are not a whole packet header (8 bytes: stream id, "
                                     "size)",
                                     left, where));
    }
    uint8_t head[8];
    if (std::fread(head, 1, 8, file_.get()) != 8)
      fail(next_offset_, std::string("read error: ") + std::strerror(errno));
    packet_stream_ = aedat4::loadLe<int32_t>(head);
    const int32_t size = aedat4::loadLe<int32_t>(head + 4);
    const auto stream = std::find_if(stats_.streams.begin(), stats_.streams.end(),
                                     [&](const ContainerStream& s) { return s.id == packet_stream_; });
    if (stream == stats_.streams.end()) {
      fail(packet_offset_, fmt::format("packet {} belongs to stream {}, which the IOHeader's info node does not list "
                                       "(streams: {}; corrupt packet header?)",
                                       packet_index_, packet_stream_, streamList(header_.streams)));
    }
    if (size < 0)
      fail(packet_offset_, fmt::format("{}: negative size {} (corrupt packet header)", packetLabel(), size));
    if (static_cast<uint64_t>(size) > left - 8) {
      fail(packet_offset_, fmt::format("truncated: {} declares {} bytes, only {} remain {}", packetLabel(), size,
                                       left - 8, where));
    }
    if (static_cast<std::size_t>(size) > kMaxPacketBytes) {
      fail(packet_offset_, fmt::format("{}: {} bytes, more than the {} MiB limit of a packet", packetLabel(), size,
                                       kMaxPacketBytes >> 20));
    }
    next_offset_ += 8 + static_cast<uint64_t>(size);
    ++stream->packets;
    const bool events = stream->id == event_stream_;
    const bool counted = stream->type == "IMUS" || stream->type == "TRIG";
    if (!events && !counted) {  // frames, other event streams, unknown types: skipped unread
      if (std::fseek(file_.get(), static_cast<long>(next_offset_), SEEK_SET) != 0)
        fail(packet_offset_, "cannot seek past " + packetLabel());
      continue;
    }
    if (payload_.size() < static_cast<std::size_t>(size)) payload_.resize(static_cast<std::size_t>(size));
    if (std::fread(payload_.data(), 1, static_cast<std::size_t>(size), file_.get()) != static_cast<std::size_t>(size))
      fail(packet_offset_, std::string("read error: ") + std::strerror(errno));
    decode(static_cast<uint32_t>(size));
    if (events) {
      const uint8_t* vector = elementsOf<aedat4::EventPacketTable>("EventPacket");
      event_count_ = vector == nullptr ? 0 : aedat4::loadLe<uint32_t>(vector);
      events_ = vector == nullptr ? nullptr : vector + sizeof(flatbuffers::uoffset_t);
      next_event_ = 0;
      stream->elements += event_count_;
      if (event_count_ > 0) return true;
      continue;
    }
    const bool imu = stream->type == "IMUS";
    const uint8_t* vector = elementsOf<aedat4::TablesPacketTable>(imu ? "IMUPacket" : "TriggerPacket");
    const uint32_t count = vector == nullptr ? 0 : aedat4::loadLe<uint32_t>(vector);
    stream->elements += count;
    (imu ? stats_.imu_samples : stats_.trigger_events) += count;
  }
}

bool Aedat4Reader::read(EventPacket& packet) {
  packet.first_index = stats_.events;
  const auto capacity = static_cast<std::size_t>(options_.packet_size);
  if (packet.events.size() != capacity) packet.events.resize(capacity);
  Event* out = packet.events.data();
  std::size_t n = 0;
  while (n < capacity) {
    if (next_event_ == event_count_ && !nextEventPacket()) break;
    const std::size_t take = std::min(capacity - n, event_count_ - next_event_);
    for (std::size_t i = 0; i < take; ++i) {
      const uint8_t* p = events_ + (next_event_ + i) * aedat4::kEventBytes;
      const auto t_us = aedat4::loadLe<int64_t>(p);
      const auto x = aedat4::loadLe<int16_t>(p + 8);
      const auto y = aedat4::loadLe<int16_t>(p + 10);
      const bool representable = t_us <= kMaxTimeUs && t_us >= -kMaxTimeUs;
      if (!representable) error_ = fmt::format("time {} µs is out of range", t_us);
      if (!representable || !checker_.accept(t_us * 1000, x, y, p[12], out[n + i], error_))
        fail(packet_offset_, fmt::format("{}, event {}: {}", packetLabel(), next_event_ + i, error_));
    }
    n += take;
    next_event_ += take;
  }
  packet.events.resize(n);
  stats_.events += n;
  stats_.clamped_times = checker_.clamped();
  return n > 0;
}

}  // namespace asynevo::io_detail
