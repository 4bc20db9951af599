#pragma once
// ROS1 bag files (format version 2.0) holding event messages: dvs_msgs/EventArray (rpg_dvs_ros) or
// event_camera_msgs/EventPacket (ros-event-camera) with EVT 3.0 / EVT 2.0 payloads.
//
// Written from the format's public specification, http://wiki.ros.org/Bags/Format/2.0, and ROS1's
// message serialization (http://wiki.ros.org/msg, http://wiki.ros.org/ROS/Technical%20Overview). The
// Debian library (librosbag-storage-dev) is not used: it trusts the lengths stored in a bag, and a single
// corrupt length inside a chunk makes it read past its buffer (docs/reference/formats_rosbag.md).
//
// The bag's index (connection and chunk-info records at its end) gives the topics and message counts;
// the chunks are then read one at a time in file order, so memory is bounded by one chunk (compressed
// and uncompressed) and a packet, whatever the bag's size.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/file_handle.hpp"
#include "event_checker.hpp"
#include "evt_decoder.hpp"

namespace asynevo::io_detail {

/// The bag magic, the first 13 bytes of every bag of format 2.0.
inline constexpr char kRosbagMagic[] = "#ROSBAG V2.0\n";
inline constexpr std::size_t kRosbagMagicBytes = sizeof(kRosbagMagic) - 1;

/// One connection record: a topic with its message type.
struct BagConnection {
  uint32_t id = 0;
  std::string topic;
  std::string type;        ///< "dvs_msgs/EventArray", ...
  std::string md5sum;
  std::string definition;  ///< the message definition text
};

/// One chunk-info record of the index: where a chunk is and how many messages of each connection it holds.
struct BagChunk {
  uint64_t pos = 0;
  std::vector<std::pair<uint32_t, uint32_t>> counts;  ///< (connection id, messages)
};

/// A topic of the bag: its name, type, MD5 sum, connections and message count (from the index).
struct BagTopic {
  std::string name, type, md5sum;
  std::vector<uint32_t> ids;
  uint64_t messages = 0;
};

/// Which non-event topic to read raw (ground truth, camera info): the accepted types with their MD5
/// sums, the topic the user named ("" = the only topic of an accepted type) and how to name things in
/// messages.
struct BagTopicQuery {
  std::vector<std::pair<std::string, std::string>> types;  ///< (type, MD5 sum) accepted
  std::string topic;                                       ///< requested by the user; "" = choose
  std::string flag;                                        ///< the option that names the topic ("--gt-topic")
  std::string what;                                        ///< "pose", "camera info"
  std::string choose;  ///< what to do when there are several ("; choose one with --gt-topic NAME")
};

class RosbagReader final : public EventReader {
 public:
  RosbagReader(const std::string& path, const ReaderOptions& options);
  /// Opens the bag to read the raw messages of one topic chosen by `query` (no events are read). When the
  /// bag holds no topic of an accepted type and none was requested, hasTopic() is false; several such
  /// topics without a requested one, a requested topic that is missing or of another type, or an MD5 sum
  /// other than the accepted one are InputErrors naming the topics or sums.
  RosbagReader(const std::string& path, const BagTopicQuery& query);
  bool hasTopic() const { return !selected_.empty(); }
  /// The next message of the chosen topic (raw mode): its serialized bytes, valid until the next call.
  bool nextRawMessage(const unsigned char*& data, std::size_t& size);
  const std::string& topic() const { return topic_; }
  const std::string& topicType() const { return topic_type_; }
  /// Every topic of the bag, in order of first appearance.
  const std::vector<BagTopic>& topics() const { return topics_; }
  /// Fails naming the file, the current message's place and index among the topic's messages.
  [[noreturn]] void failInMessage(const std::string& message) const;
  bool read(EventPacket& packet) override;
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  enum class Kind { kEventArray, kEventArray2014, kEventPacket };
  enum class Encoding { kNone, kEvt3, kEvt2 };

  void readIndex();
  void collectTopics();
  void chooseTopic();
  void chooseQueriedTopic(const BagTopicQuery& query);
  /// Loads the next chunk holding messages of the chosen topic; false when there is none.
  bool loadNextChunk();
  /// Moves to the next message of the chosen topic and parses its fields; false at the end of the bag.
  bool nextMessage();
  void parseMessage(const unsigned char* data, std::size_t size);
  std::size_t decodeMessage(Event* out, std::size_t n, std::size_t capacity);

  [[noreturn]] void failAt(uint64_t offset, const std::string& message) const;

  StreamInfo info_;
  ReaderStats stats_;
  ReaderOptions options_;
  FileHandle file_;
  uint64_t file_size_ = 0;
  uint64_t index_pos_ = 0;
  uint32_t connection_count_ = 0;
  uint32_t chunk_count_ = 0;
  std::vector<BagConnection> connections_;
  std::vector<BagChunk> chunks_;          ///< sorted by position
  std::vector<BagTopic> topics_;
  std::vector<uint32_t> selected_;        ///< connection ids of the chosen topic
  std::string topic_;
  std::string topic_type_;
  bool raw_ = false;                      ///< raw mode: messages are handed out, not decoded as events
  const unsigned char* raw_data_ = nullptr;
  std::size_t raw_size_ = 0;
  Kind kind_ = Kind::kEventArray;

  // The current chunk.
  std::size_t next_chunk_ = 0;            ///< index in chunks_ of the next chunk to load
  uint64_t chunk_pos_ = 0;                ///< file offset of the chunk record
  uint64_t chunk_data_pos_ = 0;           ///< file offset of the chunk's data
  std::string compression_;
  std::vector<unsigned char> compressed_;
  std::vector<unsigned char> chunk_;      ///< the uncompressed records
  std::size_t record_pos_ = 0;            ///< next record in chunk_
  bool have_chunk_ = false;

  // The current message.
  bool have_message_ = false;
  uint64_t message_index_ = 0;            ///< 0-based, among the chosen topic's messages
  std::size_t message_record_ = 0;        ///< offset of its record in chunk_
  const unsigned char* events_ = nullptr;  ///< its events array (EventArray) or payload (EventPacket)
  std::size_t events_size_ = 0;           ///< elements (EventArray) or bytes (EventPacket)
  std::size_t events_pos_ = 0;            ///< next element or byte
  Encoding encoding_ = Encoding::kNone;
  Evt3Decoder evt3_;
  Evt2Decoder evt2_;
  int msg_width_ = 0;
  int msg_height_ = 0;
  bool size_known_ = false;

  EventChecker checker_{1, 1, 0};
  std::string error_;
};

}  // namespace asynevo::io_detail
