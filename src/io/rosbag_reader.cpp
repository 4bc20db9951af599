// ROS1 bag (format 2.0) event reader; see rosbag_reader.hpp. Everything below follows the format
// specification at http://wiki.ros.org/Bags/Format/2.0:
//
//   file    = "#ROSBAG V2.0\n", then records
//   record  = u32 header_len, header (fields), u32 data_len, data
//   field   = u32 field_len, "name=value" (value binary; integers little-endian)
//   op 0x03 bag header:    index_pos u64, conn_count u32, chunk_count u32 (data: padding)
//   op 0x05 chunk:         compression "none" | "bz2" | "lz4", size u32 (uncompressed); data: records
//   op 0x07 connection:    conn u32, topic; data: connection header fields (type, md5sum, message_definition, ...)
//   op 0x02 message data:  conn u32, time u64 (u32 sec, u32 nsec); data: the serialized message
//   op 0x04 index data:    ver u32, conn u32, count u32; data: count x (time u64, offset u32)
//   op 0x06 chunk info:    ver u32, chunk_pos u64, start_time u64, end_time u64, count u32;
//                          data: count x (conn u32, messages u32)
//
// The index at index_pos holds conn_count connection records then chunk_count chunk-info records.
// Messages are ROS1-serialized: little-endian integers, time = u32 sec + u32 nsec, strings and
// variable arrays as a u32 element count followed by the elements.
#include "rosbag_reader.hpp"

#include <bzlib.h>
#include <fmt/format.h>
#include <lz4frame.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>

#include "asynevo/core/error.hpp"
#include "little_endian.hpp"

namespace asynevo::io_detail {

namespace {

constexpr uint32_t kMaxHeaderBytes = 1u << 20;        // a record header holds a few short fields
constexpr uint32_t kMaxIndexRecordBytes = 64u << 20;  // a connection's definition, a chunk's counts
constexpr uint64_t kMaxChunkBytes = uint64_t{256} << 20;  // recorders write chunks of ~768 KiB
constexpr const char* kEventArray = "dvs_msgs/EventArray";
constexpr const char* kEventPacket = "event_camera_msgs/EventPacket";
// MD5 sums of the message definitions read here (ROS's definition checksums; computed from the .msg
// files: dvs_msgs/Event "uint16 x, uint16 y, time ts, bool polarity").
constexpr const char* kEventArrayMd5 = "5e8beee5a6c107e504c2e78903c224b8";
constexpr const char* kEventPacketMd5 = "8a6101b351a64529ac77bd8b71074e52";
// rpg_dvs_ros's dvs_msgs from September 2014 to October 2015: EventArray was only "Event[] events" (no
// header, no size) and Event "uint16 x, uint16 y, uint64 time, bool polarity", the time in µs of the
// DVS128's clock, the only camera its driver then supported.
constexpr const char* kEventArray2014Md5 = "d2e726b2040dbc135644f4709c150a10";
constexpr int kDvs128Size = 128;
constexpr std::size_t kDvsEventBytes = 13;  // u16 x, u16 y, u32 sec, u32 nsec, u8 polarity
constexpr int kEvtLimit = 2048;             // EVT 2.0/3.0 hold 11-bit x and y


bool isEventType(const std::string& type) { return type == kEventArray || type == kEventPacket; }

/// The fields of a record header (or of a connection header): calls f(name, value) for each; returns
/// an error text, or "" when the fields are well formed.
template <typename F>
std::string forEachField(const unsigned char* p, std::size_t size, F&& f) {
  std::size_t pos = 0;
  while (pos < size) {
    if (size - pos < 4) return fmt::format("a field length at byte {} of the header is cut off", pos);
    const uint32_t len = load32(p + pos);
    pos += 4;
    if (len > size - pos) {
      return fmt::format("a header field of {} bytes at byte {} runs past the header's end ({} bytes)", len, pos - 4,
                         size);
    }
    const auto* begin = reinterpret_cast<const char*>(p + pos);
    const auto* eq = static_cast<const char*>(std::memchr(begin, '=', len));
    if (eq == nullptr) return fmt::format("a header field at byte {} has no '='", pos - 4);
    const std::string_view name(begin, static_cast<std::size_t>(eq - begin));
    f(name, reinterpret_cast<const unsigned char*>(eq + 1), len - name.size() - 1);
    pos += len;
  }
  return "";
}

/// The fields of one record header that this reader uses.
struct RecordFields {
  int op = -1;
  bool has_conn = false, has_index_pos = false, has_conn_count = false, has_chunk_count = false,
       has_chunk_pos = false, has_count = false, has_size = false;
  uint32_t conn = 0, conn_count = 0, chunk_count = 0, count = 0, size = 0;
  uint64_t index_pos = 0, chunk_pos = 0;
  std::string topic, compression, encryptor;
};

std::string parseRecordFields(const unsigned char* p, std::size_t size, RecordFields& out) {
  std::string wrong;
  std::string error = forEachField(p, size, [&](std::string_view name, const unsigned char* v, std::size_t n) {
    auto u32 = [&](bool& has, uint32_t& value) {
      if (n != 4) wrong = std::string(name);
      else { has = true; value = load32(v); }
    };
    auto u64 = [&](bool& has, uint64_t& value) {
      if (n != 8) wrong = std::string(name);
      else { has = true; value = load64(v); }
    };
    if (name == "op") {
      if (n != 1) wrong = "op";
      else out.op = v[0];
    } else if (name == "conn") {
      u32(out.has_conn, out.conn);
    } else if (name == "index_pos") {
      u64(out.has_index_pos, out.index_pos);
    } else if (name == "conn_count") {
      u32(out.has_conn_count, out.conn_count);
    } else if (name == "chunk_count") {
      u32(out.has_chunk_count, out.chunk_count);
    } else if (name == "chunk_pos") {
      u64(out.has_chunk_pos, out.chunk_pos);
    } else if (name == "count") {
      u32(out.has_count, out.count);
    } else if (name == "size") {
      u32(out.has_size, out.size);
    } else if (name == "topic") {
      out.topic.assign(reinterpret_cast<const char*>(v), n);
    } else if (name == "compression") {
      out.compression.assign(reinterpret_cast<const char*>(v), n);
    } else if (name == "encryptor") {
      out.encryptor.assign(reinterpret_cast<const char*>(v), n);
    }
  });
  if (!error.empty()) return error;
  if (!wrong.empty()) return "the header field '" + wrong + "' has the wrong size";
  if (out.op < 0) return "the record header has no 'op' field";
  return "";
}

/// Reads a ROS1-serialized message field by field, with every length checked against the message size.
class MessageCursor {
 public:
  MessageCursor(const unsigned char* data, std::size_t size) : data_(data), size_(size) {}
  /// Fails (returns false with `error` set) when fewer than n bytes remain.
  bool need(std::size_t n, const char* what, std::string& error) const {
    if (n <= size_ - pos_) return true;
    error = fmt::format("malformed message: {} needs {} bytes at byte {} but the message has only {} bytes", what, n,
                        pos_, size_);
    return false;
  }
  uint32_t u32() { pos_ += 4; return load32(data_ + pos_ - 4); }
  uint64_t u64() { pos_ += 8; return load64(data_ + pos_ - 8); }
  uint8_t u8() { return data_[pos_++]; }
  void skip(std::size_t n) { pos_ += n; }
  const unsigned char* here() const { return data_ + pos_; }
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return size_ - pos_; }

 private:
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace

// ---------------------------------------------------------------------------------------------------

RosbagReader::RosbagReader(const std::string& path, const ReaderOptions& options)
    : options_(options), file_(openFile(path, "rb")) {
  if (!file_) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  info_.path = path;
  info_.format = "rosbag";
  if (std::fseek(file_.get(), 0, SEEK_END) != 0) throw InputError(path, "cannot seek in the file");
  file_size_ = static_cast<uint64_t>(std::ftell(file_.get()));
  std::rewind(file_.get());
  if (file_size_ == 0) throw InputError(path, "the event file is empty");
  char magic[kRosbagMagicBytes] = {};
  const std::size_t got = std::fread(magic, 1, sizeof(magic), file_.get());
  if (got != sizeof(magic) || std::memcmp(magic, kRosbagMagic, sizeof(magic)) != 0) {
    std::string first(magic, got);
    first = first.substr(0, first.find('\n'));
    if (first.rfind("#ROSBAG V", 0) == 0) {
      failAt(0, "the version line '" + first + "' names a bag format AsynEVO does not read (only '#ROSBAG V2.0'; "
                "convert older bags with 'rosbag fix')");
    }
    failAt(0, "not a ROS bag: the file does not start with '#ROSBAG V2.0' (truncated, or another format?)");
  }
  readIndex();
  chooseTopic();

  // The sensor size comes from the messages: the first message of the topic states it.
  const bool configured = options_.width > 0 && options_.height > 0;
  if (kind_ == Kind::kEventArray2014) {
    // This revision's messages state no size: the configured one, else the DVS128's.
    if (configured) {
      info_.width = options_.width;
      info_.height = options_.height;
      info_.size_origin = options_.size_origin;
    } else {
      info_.width = info_.height = kDvs128Size;
      info_.size_origin = "the DVS128 default (the 2014-15 dvs_msgs/EventArray states no size)";
    }
    checker_ = EventChecker(info_.width, info_.height, options_.max_time_reversal_ns, info_.size_origin, true);
    if (!nextMessage())
      throw InputError(path, "the event topic " + topic_ + " has no messages: the file holds no events");
  } else if (nextMessage()) {
    if (msg_width_ == 0 && msg_height_ == 0 && configured) {
      info_.width = options_.width;
      info_.height = options_.height;
      info_.size_origin = options_.size_origin;
      checker_ = EventChecker(info_.width, info_.height, options_.max_time_reversal_ns, info_.size_origin, true);
    } else {
      if (msg_width_ == 0 || msg_height_ == 0) {
        failInMessage(fmt::format("the message states a {}x{} sensor; give the size with --sensor WxH", msg_width_,
                                  msg_height_));
      }
      if (configured && (options_.width != msg_width_ || options_.height != msg_height_)) {
        failInMessage(fmt::format("sensor size {}x{} in the message differs from {}x{} set by {} (the bag's own size "
                                  "is kept only when they agree: correct or drop that setting)",
                                  msg_width_, msg_height_, options_.width, options_.height, options_.size_origin));
      }
      info_.width = msg_width_;
      info_.height = msg_height_;
      info_.size_origin = "the bag's messages";
      checker_ = EventChecker(info_.width, info_.height, options_.max_time_reversal_ns, info_.size_origin, false);
    }
    size_known_ = true;
  } else {
    // No message states a size, and no event will be delivered.
    throw InputError(path, "the event topic " + topic_ + " has no messages: the file holds no events");
  }
}

RosbagReader::RosbagReader(const std::string& path, const BagTopicQuery& query) : file_(openFile(path, "rb")) {
  if (!file_) throw InputError(path, std::string("cannot open the bag: ") + std::strerror(errno));
  info_.path = path;
  info_.format = "rosbag";
  raw_ = true;
  if (std::fseek(file_.get(), 0, SEEK_END) != 0) throw InputError(path, "cannot seek in the file");
  file_size_ = static_cast<uint64_t>(std::ftell(file_.get()));
  std::rewind(file_.get());
  char magic[kRosbagMagicBytes] = {};
  if (std::fread(magic, 1, sizeof(magic), file_.get()) != sizeof(magic) ||
      std::memcmp(magic, kRosbagMagic, sizeof(magic)) != 0) {
    failAt(0, "not a ROS bag of format 2.0: the file does not start with '#ROSBAG V2.0'");
  }
  readIndex();
  chooseQueriedTopic(query);
}

void RosbagReader::chooseQueriedTopic(const BagTopicQuery& query) {
  collectTopics();
  auto accepted = [&](const BagTopic& t) {
    return std::any_of(query.types.begin(), query.types.end(), [&](const auto& a) { return a.first == t.type; });
  };
  auto list = [&](bool accepted_only) {
    std::string text;
    for (const BagTopic& t : topics_) {
      if (accepted_only && !accepted(t)) continue;
      text += (text.empty() ? "" : ", ") + fmt::format("{} ({}, {} messages)", t.name, t.type, t.messages);
    }
    return text.empty() ? std::string("none") : text;
  };
  std::string types;
  for (const auto& a : query.types) types += (types.empty() ? "" : ", ") + a.first;
  const BagTopic* chosen = nullptr;
  if (!query.topic.empty()) {
    for (const BagTopic& t : topics_) {
      if (t.name == query.topic) chosen = &t;
    }
    if (chosen == nullptr) {
      failAt(index_pos_, fmt::format("the bag has no topic '{}' ({}); its topics: {}", query.topic, query.flag,
                                     list(false)));
    }
    if (!accepted(*chosen)) {
      failAt(index_pos_, fmt::format("topic {} ({}) holds {} messages, not a {} type AsynEVO reads ({}); {} topics: {}",
                                     chosen->name, query.flag, chosen->type, query.what, types, query.what, list(true)));
    }
  } else {
    std::vector<const BagTopic*> found;
    for (const BagTopic& t : topics_) {
      if (accepted(t)) found.push_back(&t);
    }
    if (found.empty()) return;  // hasTopic() is false
    if (found.size() > 1) {
      failAt(index_pos_, fmt::format("the bag has {} {} topics: {}{}", found.size(), query.what, list(true),
                                     query.choose));
    }
    chosen = found.front();
  }
  std::string expected;
  for (const auto& a : query.types) {
    if (a.first == chosen->type) expected = a.second;
  }
  if (chosen->md5sum != expected) {
    failAt(index_pos_, fmt::format("topic {} has a revision of {} with MD5 sum '{}'; AsynEVO reads the revision with MD5 "
                                   "sum {} (docs/reference/formats_rosbag.md)",
                                   chosen->name, chosen->type, chosen->md5sum, expected));
  }
  topic_ = chosen->name;
  topic_type_ = chosen->type;
  selected_ = chosen->ids;
}

bool RosbagReader::nextRawMessage(const unsigned char*& data, std::size_t& size) {
  if (selected_.empty() || !nextMessage()) return false;
  data = raw_data_;
  size = raw_size_;
  return true;
}

void RosbagReader::failAt(uint64_t offset, const std::string& message) const {
  throw InputError::atByte(info_.path, offset, message);
}

void RosbagReader::failInMessage(const std::string& message) const {
  if (compression_ == "none") {
    failAt(chunk_data_pos_ + message_record_,
           fmt::format("message {} of topic {}: {}", message_index_, topic_, message));
  }
  failAt(chunk_pos_, fmt::format("message {} of topic {} (record at byte {} of this {} chunk's {} uncompressed bytes): "
                                 "{}",
                                 message_index_, topic_, message_record_, compression_, chunk_.size(), message));
}

void RosbagReader::readIndex() {
  // The bag header record right after the magic.
  unsigned char len[4];
  auto readExact = [&](uint64_t offset, void* out, std::size_t n, const char* what) {
    if (offset > file_size_ || n > file_size_ - offset) {
      failAt(offset, fmt::format("truncated: {} ({} bytes) runs past the end of the file ({} bytes)", what, n, file_size_));
    }
    if (std::fseek(file_.get(), static_cast<long>(offset), SEEK_SET) != 0 ||
        std::fread(out, 1, n, file_.get()) != n) {
      failAt(offset, std::string("read error: ") + std::strerror(errno));
    }
  };
  // Reads the record at `offset`: its header fields and data; returns the offset after it. Errors name
  // the record's offset.
  std::vector<unsigned char> header, data;
  auto readRecord = [&](uint64_t offset, RecordFields& fields, const char* what, uint32_t max_data) -> uint64_t {
    auto need = [&](uint64_t end) {
      if (end > file_size_) {
        failAt(offset, fmt::format("truncated: {} needs bytes up to {} but the file has only {} bytes", what, end,
                                   file_size_));
      }
    };
    need(offset + 4);
    readExact(offset, len, 4, what);
    const uint32_t header_len = load32(len);
    if (header_len > kMaxHeaderBytes)
      failAt(offset, fmt::format("corrupt {}: header length {} bytes (more than 1 MiB)", what, header_len));
    need(offset + 8 + header_len);
    header.resize(header_len);
    readExact(offset + 4, header.data(), header_len, what);
    readExact(offset + 4 + header_len, len, 4, what);
    const uint32_t data_len = load32(len);
    if (data_len > max_data)
      failAt(offset, fmt::format("corrupt {}: data length {} bytes (more than {} MiB)", what, data_len, max_data >> 20));
    need(offset + 8 + header_len + data_len);
    data.resize(data_len);
    readExact(offset + 8 + header_len, data.data(), data_len, what);
    fields = RecordFields();
    const std::string error = parseRecordFields(header.data(), header.size(), fields);
    if (!error.empty()) failAt(offset, std::string("corrupt ") + what + ": " + error);
    return offset + 8 + header_len + data_len;
  };

  RecordFields bag;
  readRecord(kRosbagMagicBytes, bag, "bag header record", kMaxIndexRecordBytes);
  if (bag.op != 0x03 || !bag.has_index_pos || !bag.has_conn_count || !bag.has_chunk_count) {
    failAt(kRosbagMagicBytes, "corrupt bag: the first record is not a bag header (op 0x03 with index_pos, conn_count "
                              "and chunk_count)");
  }
  if (!bag.encryptor.empty() && bag.encryptor != "rosbag/NoEncryptor") {
    failAt(kRosbagMagicBytes, "the bag is encrypted (encryptor '" + bag.encryptor + "'); decrypt it with ROS1's rosbag "
                              "tools first");
  }
  index_pos_ = bag.index_pos;
  connection_count_ = bag.conn_count;
  chunk_count_ = bag.chunk_count;
  if (index_pos_ == 0) {
    failAt(kRosbagMagicBytes, "the bag has no index (its recording was not closed properly); rebuild it with "
                              "'rosbag reindex'");
  }
  if (index_pos_ >= file_size_) {
    failAt(kRosbagMagicBytes, fmt::format("truncated: the bag header puts the index at byte {} but the file has only {} "
                                          "bytes (cut short? 'rosbag reindex' rebuilds the index of what is left)",
                                          index_pos_, file_size_));
  }

  uint64_t at = index_pos_;
  for (uint32_t i = 0; i < connection_count_; ++i) {
    RecordFields f;
    const uint64_t record = at;
    at = readRecord(at, f, "connection record", kMaxIndexRecordBytes);
    if (f.op != 0x07 || !f.has_conn) {
      failAt(record, fmt::format("corrupt index: record {} of the index is not a connection record (op 0x07), "
                                 "though the bag header announces {} connections", i, connection_count_));
    }
    BagConnection c;
    c.id = f.conn;
    c.topic = f.topic;
    const std::string error = forEachField(data.data(), data.size(), [&](std::string_view name, const unsigned char* v,
                                                                         std::size_t n) {
      const std::string value(reinterpret_cast<const char*>(v), n);
      if (name == "type") c.type = value;
      else if (name == "md5sum") c.md5sum = value;
      else if (name == "message_definition") c.definition = value;
      else if (name == "topic" && c.topic.empty()) c.topic = value;
    });
    if (!error.empty()) failAt(record, "corrupt connection record: " + error);
    connections_.push_back(std::move(c));
  }
  for (uint32_t i = 0; i < chunk_count_; ++i) {
    RecordFields f;
    const uint64_t record = at;
    at = readRecord(at, f, "chunk info record", kMaxIndexRecordBytes);
    if (f.op != 0x06 || !f.has_chunk_pos || !f.has_count) {
      failAt(record, fmt::format("corrupt index: record {} after the connections is not a chunk info record (op "
                                 "0x06), though the bag header announces {} chunks", i, chunk_count_));
    }
    if (static_cast<uint64_t>(f.count) * 8 != data.size()) {
      failAt(record, fmt::format("corrupt chunk info record: {} connections need {} bytes, the record has {}", f.count,
                                 uint64_t{f.count} * 8, data.size()));
    }
    if (f.chunk_pos < kRosbagMagicBytes || f.chunk_pos >= index_pos_) {
      failAt(record, fmt::format("corrupt chunk info record: chunk position {} is outside the chunk area (bytes {} to "
                                 "{})", f.chunk_pos, kRosbagMagicBytes, index_pos_));
    }
    BagChunk chunk;
    chunk.pos = f.chunk_pos;
    for (uint32_t k = 0; k < f.count; ++k) chunk.counts.emplace_back(load32(&data[8 * k]), load32(&data[8 * k + 4]));
    chunks_.push_back(std::move(chunk));
  }
  std::stable_sort(chunks_.begin(), chunks_.end(), [](const BagChunk& a, const BagChunk& b) { return a.pos < b.pos; });
  for (std::size_t i = 1; i < chunks_.size(); ++i) {
    if (chunks_[i].pos == chunks_[i - 1].pos) {
      failAt(index_pos_, fmt::format("corrupt index: two chunk info records for the chunk at byte {}", chunks_[i].pos));
    }
  }
}

void RosbagReader::collectTopics() {
  // Topics in order of first appearance, with their types and message counts.
  using Topic = BagTopic;
  std::vector<BagTopic>& topics = topics_;
  for (const BagConnection& c : connections_) {
    auto it = std::find_if(topics.begin(), topics.end(), [&](const Topic& t) { return t.name == c.topic; });
    if (it == topics.end()) {
      topics.push_back({c.topic, c.type, c.md5sum, {}, 0});
      it = topics.end() - 1;
    } else if (it->type != c.type || it->md5sum != c.md5sum) {
      failAt(index_pos_, fmt::format("topic {} has connections of two types ({} and {}); AsynEVO reads one type per "
                                     "topic", c.topic, it->type, c.type));
    }
    it->ids.push_back(c.id);
  }
  for (const BagChunk& chunk : chunks_) {
    for (const auto& [id, count] : chunk.counts) {
      for (Topic& t : topics) {
        if (std::find(t.ids.begin(), t.ids.end(), id) != t.ids.end()) t.messages += count;
      }
    }
  }
}

void RosbagReader::chooseTopic() {
  using Topic = BagTopic;
  collectTopics();
  const std::vector<BagTopic>& topics = topics_;
  auto describe = [](const Topic& t) { return fmt::format("{} ({}, {} messages)", t.name, t.type, t.messages); };
  auto list = [&](bool events_only) {
    std::string text;
    for (const Topic& t : topics) {
      if (events_only && !isEventType(t.type)) continue;
      text += (text.empty() ? "" : ", ") + describe(t);
    }
    return text.empty() ? std::string("none") : text;
  };
  const Topic* chosen = nullptr;
  if (!options_.topic.empty()) {
    for (const Topic& t : topics) {
      if (t.name == options_.topic) chosen = &t;
    }
    if (chosen == nullptr) {
      failAt(index_pos_, fmt::format("the bag has no topic '{}' (--topic); its topics: {}", options_.topic, list(false)));
    }
    if (!isEventType(chosen->type)) {
      failAt(index_pos_, fmt::format("topic {} (--topic) holds {} messages, not events ({} or {}); event topics: {}",
                                     chosen->name, chosen->type, kEventArray, kEventPacket, list(true)));
    }
  } else {
    std::vector<const Topic*> event_topics;
    for (const Topic& t : topics) {
      if (isEventType(t.type)) event_topics.push_back(&t);
    }
    if (event_topics.empty()) {
      failAt(index_pos_, fmt::format("the bag has no event topic (of type {} or {}); its topics: {}", kEventArray,
                                     kEventPacket, list(false)));
    }
    if (event_topics.size() > 1) {
      failAt(index_pos_, fmt::format("the bag has {} event topics: {}; choose one with --topic NAME",
                                     event_topics.size(), list(true)));
    }
    chosen = event_topics.front();
  }
  const char* expected = chosen->type == kEventArray ? kEventArrayMd5 : kEventPacketMd5;
  const bool revision_2014 = chosen->type == kEventArray && chosen->md5sum == kEventArray2014Md5;
  if (chosen->md5sum != expected && !revision_2014) {
    failAt(index_pos_, fmt::format("topic {} has a revision of {} with MD5 sum '{}'; AsynEVO reads the revision with MD5 "
                                   "sum {}{} (docs/reference/formats_rosbag.md)",
                                   chosen->name, chosen->type, chosen->md5sum, expected,
                                   chosen->type == kEventArray ? std::string(" or the 2014-15 one, ") + kEventArray2014Md5
                                                               : std::string()));
  }
  topic_ = chosen->name;
  topic_type_ = chosen->type;
  selected_ = chosen->ids;
  kind_ = revision_2014 ? Kind::kEventArray2014 : chosen->type == kEventArray ? Kind::kEventArray : Kind::kEventPacket;
  for (std::size_t i = 0; i < topics.size(); ++i) {
    ContainerStream s;
    s.id = static_cast<int>(i);
    s.type = topics[i].type;
    s.name = topics[i].name;
    s.packets = topics[i].messages;
    s.delivered = &topics[i] == chosen;
    stats_.streams.push_back(std::move(s));
  }
}

bool RosbagReader::loadNextChunk() {
  for (; next_chunk_ < chunks_.size(); ++next_chunk_) {
    const BagChunk& chunk = chunks_[next_chunk_];
    const bool wanted = std::any_of(chunk.counts.begin(), chunk.counts.end(), [&](const auto& c) {
      return c.second > 0 && std::find(selected_.begin(), selected_.end(), c.first) != selected_.end();
    });
    if (wanted) break;
  }
  if (next_chunk_ == chunks_.size()) return false;
  chunk_pos_ = chunks_[next_chunk_++].pos;
  compression_ = "none";  // until the chunk header says otherwise (messages before that name the file offset)

  // The chunk record's header: read the lengths, then the fields.
  auto readAt = [&](uint64_t offset, void* out, std::size_t n) {
    if (offset > file_size_ || n > file_size_ - offset) {
      failAt(chunk_pos_, fmt::format("truncated or corrupt chunk: its record needs bytes up to {} but the file has "
                                     "only {} bytes", offset + n, file_size_));
    }
    if (std::fseek(file_.get(), static_cast<long>(offset), SEEK_SET) != 0 ||
        std::fread(out, 1, n, file_.get()) != n) {
      failAt(offset, std::string("read error: ") + std::strerror(errno));
    }
  };
  unsigned char len[4];
  readAt(chunk_pos_, len, 4);
  const uint32_t header_len = load32(len);
  if (header_len > kMaxHeaderBytes)
    failAt(chunk_pos_, fmt::format("corrupt chunk: header length {} bytes (more than 1 MiB)", header_len));
  std::vector<unsigned char> header(header_len);
  readAt(chunk_pos_ + 4, header.data(), header_len);
  readAt(chunk_pos_ + 4 + header_len, len, 4);
  const uint32_t data_len = load32(len);
  chunk_data_pos_ = chunk_pos_ + 8 + header_len;
  if (data_len > file_size_ - chunk_data_pos_) {  // checked before any buffer of that size is allocated
    failAt(chunk_pos_, fmt::format("truncated or corrupt chunk: its {} bytes of data run past the end of the file ({} "
                                   "bytes)", data_len, file_size_));
  }
  RecordFields f;
  const std::string error = parseRecordFields(header.data(), header.size(), f);
  if (!error.empty()) failAt(chunk_pos_, "corrupt chunk: " + error);
  if (f.op != 0x05 || !f.has_size || f.compression.empty())
    failAt(chunk_pos_, "corrupt index: the chunk info points to a record that is not a chunk (op 0x05 with "
                       "compression and size)");
  if (f.size > kMaxChunkBytes) {
    failAt(chunk_pos_, fmt::format("corrupt chunk: {} bytes uncompressed (more than {} MiB)", f.size,
                                   kMaxChunkBytes >> 20));
  }
  if (f.compression == "none") {
    if (f.size != data_len) {
      failAt(chunk_pos_, fmt::format("corrupt chunk: uncompressed, but its size field ({}) differs from its data length "
                                     "({})", f.size, data_len));
    }
    chunk_.resize(data_len);
    readAt(chunk_data_pos_, chunk_.data(), data_len);
  } else if (f.compression == "lz4" || f.compression == "bz2") {
    compressed_.resize(data_len);
    readAt(chunk_data_pos_, compressed_.data(), data_len);
    // The output grows with what actually decompresses (up to the stated size), so a corrupt size
    // field cannot make the reader allocate hundreds of MiB for a few bytes of input.
    std::size_t out_pos = 0;
    auto room = [&]() {
      if (out_pos == chunk_.size()) {
        const std::size_t grown = std::max<std::size_t>(chunk_.size() * 2, std::size_t{1} << 16);
        chunk_.resize(std::min<std::size_t>(grown, f.size));
      }
      return chunk_.size() - out_pos;
    };
    chunk_.resize(std::min<std::size_t>(f.size, std::max<std::size_t>(chunk_.capacity(), std::size_t{4} * data_len)));
    std::string failure;
    if (f.compression == "bz2") {
      bz_stream stream{};
      if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) throw std::bad_alloc();
      stream.next_in = reinterpret_cast<char*>(compressed_.data());
      stream.avail_in = data_len;
      for (;;) {
        const std::size_t free = room();
        if (free == 0) {
          failure = "it decompresses to more than the chunk's stated size";
          break;
        }
        stream.next_out = reinterpret_cast<char*>(chunk_.data() + out_pos);
        stream.avail_out = static_cast<unsigned int>(std::min<std::size_t>(free, 1u << 30));
        const unsigned int before = stream.avail_out;
        const int rc = BZ2_bzDecompress(&stream);
        out_pos += before - stream.avail_out;
        if (rc == BZ_STREAM_END) break;
        if (rc != BZ_OK) {
          failure = fmt::format("libbz2 failure {}", rc);
          break;
        }
        if (stream.avail_in == 0 && stream.avail_out > 0) {
          failure = "the bz2 stream is cut off";
          break;
        }
      }
      BZ2_bzDecompressEnd(&stream);
    } else {
      LZ4F_dctx* ctx = nullptr;
      if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) throw std::bad_alloc();
      std::size_t in_pos = 0, hint = 1;
      while (in_pos < data_len && hint != 0) {
        const std::size_t free = room();
        if (free == 0) {
          failure = "it decompresses to more than the chunk's stated size";
          break;
        }
        std::size_t src = data_len - in_pos, dst = free;
        hint = LZ4F_decompress(ctx, chunk_.data() + out_pos, &dst, compressed_.data() + in_pos, &src, nullptr);
        if (LZ4F_isError(hint)) {
          failure = LZ4F_getErrorName(hint);
          break;
        }
        in_pos += src;
        out_pos += dst;
      }
      LZ4F_freeDecompressionContext(ctx);
      if (failure.empty() && hint != 0) failure = "the frame is cut off";
    }
    if (failure.empty() && out_pos != f.size) failure = fmt::format("{} bytes instead of the stated {}", out_pos, f.size);
    if (!failure.empty()) failAt(chunk_pos_, "corrupt " + f.compression + " chunk: " + failure);
    chunk_.resize(out_pos);
  } else {
    failAt(chunk_pos_, "chunk compression '" + f.compression + "' is not one of none, bz2, lz4");
  }
  compression_ = f.compression;
  record_pos_ = 0;
  have_chunk_ = true;
  return true;
}

bool RosbagReader::nextMessage() {
  for (;;) {
    if (!have_chunk_ || record_pos_ == chunk_.size()) {
      have_chunk_ = false;
      if (!loadNextChunk()) return false;
      continue;
    }
    const std::size_t record = record_pos_;
    const std::size_t left = chunk_.size() - record;
    auto corrupt = [&](const std::string& what) {
      message_record_ = record;
      if (compression_ == "none") failAt(chunk_data_pos_ + record, "corrupt record in a chunk: " + what);
      failAt(chunk_pos_, fmt::format("corrupt record at byte {} of this {} chunk's {} uncompressed bytes: {}", record,
                                     compression_, chunk_.size(), what));
    };
    if (left < 4) corrupt("the chunk ends inside a record length");
    const uint32_t header_len = load32(&chunk_[record]);
    if (header_len > left - 4 || left - 4 - header_len < 4)
      corrupt(fmt::format("header length {} runs past the chunk's end", header_len));
    const uint32_t data_len = load32(&chunk_[record + 4 + header_len]);
    const std::size_t data_at = record + 8 + header_len;
    if (data_len > chunk_.size() - data_at) corrupt(fmt::format("data length {} runs past the chunk's end", data_len));
    record_pos_ = data_at + data_len;
    int op = -1;
    uint32_t conn = 0;
    bool has_conn = false;
    const std::string error = forEachField(&chunk_[record + 4], header_len,
                                           [&](std::string_view name, const unsigned char* v, std::size_t n) {
                                             if (name == "op" && n == 1) op = v[0];
                                             if (name == "conn" && n == 4) {
                                               conn = load32(v);
                                               has_conn = true;
                                             }
                                           });
    if (!error.empty()) corrupt(error);
    if (op != 0x02) continue;  // connection records (repeated in chunks) and others
    if (!has_conn) corrupt("a message record without a 'conn' field");
    if (std::find(selected_.begin(), selected_.end(), conn) == selected_.end()) continue;
    if (have_message_) ++message_index_;
    have_message_ = true;
    message_record_ = record;
    if (raw_) {
      raw_data_ = &chunk_[data_at];
      raw_size_ = data_len;
    } else {
      parseMessage(&chunk_[data_at], data_len);
    }
    return true;
  }
}

void RosbagReader::parseMessage(const unsigned char* data, std::size_t size) {
  MessageCursor m(data, size);
  if (kind_ == Kind::kEventArray2014) {  // Event[] events only
    if (!m.need(4, "the events array length", error_)) failInMessage(error_);
    const uint32_t count = m.u32();
    if (uint64_t{count} * kDvsEventBytes != m.left()) {
      failInMessage(fmt::format("malformed message: {} events of {} bytes need {} bytes, the message has {} left after "
                                "the array length",
                                count, kDvsEventBytes, uint64_t{count} * kDvsEventBytes, m.left()));
    }
    events_ = m.here();
    events_size_ = count;
    events_pos_ = 0;
    return;
  }
  // std_msgs/Header: u32 seq, time stamp, string frame_id
  if (!m.need(16, "the header", error_)) failInMessage(error_);
  m.skip(12);
  const uint32_t frame_len = m.u32();
  if (!m.need(frame_len, "the header's frame_id", error_)) failInMessage(error_);
  m.skip(frame_len);
  if (!m.need(8, "height and width", error_)) failInMessage(error_);
  const uint32_t height = m.u32();
  const uint32_t width = m.u32();
  const uint32_t limit = kind_ == Kind::kEventPacket ? kEvtLimit : 65535;
  if (width > limit || height > limit)
    failInMessage(fmt::format("the message states a {}x{} sensor, beyond {} pixels", width, height, limit));
  if (size_known_ && (static_cast<int>(width) != msg_width_ || static_cast<int>(height) != msg_height_)) {
    failInMessage(fmt::format("the message states a {}x{} sensor, the topic's first message {}x{}", width, height,
                              msg_width_, msg_height_));
  }
  msg_width_ = static_cast<int>(width);
  msg_height_ = static_cast<int>(height);
  if (kind_ == Kind::kEventArray) {
    if (!m.need(4, "the events array length", error_)) failInMessage(error_);
    const uint32_t count = m.u32();
    if (uint64_t{count} * kDvsEventBytes != m.left()) {
      failInMessage(fmt::format("malformed message: {} events of {} bytes need {} bytes, the message has {} left after "
                                "its header (a message type other than {}?)",
                                count, kDvsEventBytes, uint64_t{count} * kDvsEventBytes, m.left(), kEventArray));
    }
    events_ = m.here();
    events_size_ = count;
  } else {
    if (!m.need(16, "seq and time_base", error_)) failInMessage(error_);
    m.skip(16);
    if (!m.need(4, "the encoding's length", error_)) failInMessage(error_);
    const uint32_t encoding_len = m.u32();
    if (!m.need(encoding_len, "the encoding", error_)) failInMessage(error_);
    const std::string encoding(reinterpret_cast<const char*>(m.here()), encoding_len);
    m.skip(encoding_len);
    if (!m.need(5, "is_bigendian and the events length", error_)) failInMessage(error_);
    const uint8_t big_endian = m.u8();
    const uint32_t bytes = m.u32();
    if (bytes != m.left()) {
      failInMessage(fmt::format("malformed message: an events payload of {} bytes, but the message has {} left",
                                bytes, m.left()));
    }
    Encoding e = Encoding::kNone;
    if (encoding == "evt3") e = Encoding::kEvt3;
    else if (encoding == "evt2") e = Encoding::kEvt2;
    else failInMessage("encoding '" + encoding + "' is not decoded by AsynEVO (supported: evt3, evt2)");
    if (big_endian != 0) failInMessage("is_bigendian is set: only little-endian EVT payloads are decoded");
    if (encoding_ != Encoding::kNone && e != encoding_)
      failInMessage("encoding '" + encoding + "' differs from the topic's first message");
    if (encoding_ == Encoding::kNone) {
      encoding_ = e;
      evt3_.reset();
      evt2_.reset();
    }
    const std::size_t word = e == Encoding::kEvt3 ? 2 : 4;
    if (bytes % word != 0) {
      failInMessage(fmt::format("an events payload of {} bytes is not a whole number of {}-byte {} words", bytes, word,
                                e == Encoding::kEvt3 ? "EVT 3.0" : "EVT 2.0"));
    }
    events_ = m.here();
    events_size_ = bytes;
  }
  events_pos_ = 0;
}

std::size_t RosbagReader::decodeMessage(Event* out, std::size_t n, std::size_t capacity) {
  if (kind_ == Kind::kEventArray2014) {
    const std::size_t take = std::min(capacity - n, events_size_ - events_pos_);
    const unsigned char* p = events_ + events_pos_ * kDvsEventBytes;
    for (std::size_t i = 0; i < take; ++i, p += kDvsEventBytes) {
      const uint64_t t_us = load64(p + 4);
      if (t_us > static_cast<uint64_t>(INT64_MAX) / 1000)
        failInMessage(fmt::format("event {}: time {} µs is out of range", events_pos_ + i, t_us));
      if (!checker_.accept(static_cast<int64_t>(t_us) * 1000, load16(p), load16(p + 2), p[12], out[n + i], error_))
        failInMessage(fmt::format("event {}: {}", events_pos_ + i, error_));
    }
    events_pos_ += take;
    return n + take;
  }
  if (kind_ == Kind::kEventArray) {
    const std::size_t take = std::min(capacity - n, events_size_ - events_pos_);
    const unsigned char* p = events_ + events_pos_ * kDvsEventBytes;
    for (std::size_t i = 0; i < take; ++i, p += kDvsEventBytes) {
      const uint32_t sec = load32(p + 4);
      const uint32_t nsec = load32(p + 8);
      if (nsec >= 1'000'000'000u) {
        failInMessage(fmt::format("event {}: time {} s + {} ns has a nanosecond part of 10^9 or more", events_pos_ + i,
                                  sec, nsec));
      }
      const int64_t t_ns = static_cast<int64_t>(sec) * 1'000'000'000 + nsec;
      if (!checker_.accept(t_ns, load16(p), load16(p + 2), p[12], out[n + i], error_))
        failInMessage(fmt::format("event {}: {}", events_pos_ + i, error_));
    }
    events_pos_ += take;
    return n + take;
  }
  try {
    if (encoding_ == Encoding::kEvt3)
      return evt3_.decode(events_, events_pos_, events_size_, 0, out, n, capacity, checker_, stats_);
    return evt2_.decode(events_, events_pos_, events_size_, 0, out, n, capacity, checker_, stats_);
  } catch (const EvtDecodeError& e) {
    failInMessage(fmt::format("byte {} of its {} payload: {}", e.offset, encoding_ == Encoding::kEvt3 ? "EVT 3.0" : "EVT 2.0",
                              e.message));
  }
}

bool RosbagReader::read(EventPacket& packet) {
  packet.first_index = stats_.events;
  const auto capacity = static_cast<std::size_t>(options_.packet_size);
  if (packet.events.size() != capacity) packet.events.resize(capacity);
  std::size_t n = 0;
  while (n < capacity && have_message_) {
    n = decodeMessage(packet.events.data(), n, capacity);
    const bool pending = encoding_ == Encoding::kEvt3 && evt3_.pending();
    if (events_pos_ == events_size_ && !pending) {
      if (!nextMessage()) have_message_ = false;
    }
  }
  packet.events.resize(n);
  stats_.events += n;
  stats_.clamped_times = checker_.clamped();
  for (ContainerStream& s : stats_.streams) {
    if (s.delivered) s.elements = stats_.events;
  }
  return n > 0;
}

}  // namespace asynevo::io_detail
