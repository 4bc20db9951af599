#pragma once
// ROS1 bags built byte by byte from the format specification (http://wiki.ros.org/Bags/Format/2.0) and
// ROS1 message serialization, with no bag library: the reader is tested against the specification, not
// against another implementation. Used by tests/io/rosbag_reader_test.cpp and the fuzz seed maker.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace asynevo::testing::bag {

inline std::string u8(uint32_t v) { return std::string(1, static_cast<char>(v & 0xFF)); }
inline std::string u16(uint32_t v) { return u8(v) + u8(v >> 8); }
inline std::string u32(uint32_t v) { return u16(v & 0xFFFF) + u16(v >> 16); }
inline std::string u64(uint64_t v) { return u32(static_cast<uint32_t>(v)) + u32(static_cast<uint32_t>(v >> 32)); }
/// ROS time: u32 seconds, u32 nanoseconds.
inline std::string rosTime(uint64_t t_ns) {
  return u32(static_cast<uint32_t>(t_ns / 1'000'000'000)) + u32(static_cast<uint32_t>(t_ns % 1'000'000'000));
}
/// ROS string or uint8[]: u32 length, then the bytes.
inline std::string rosString(const std::string& s) { return u32(static_cast<uint32_t>(s.size())) + s; }

/// One header field: u32 length of "name=value", then "name=value".
inline std::string field(const std::string& name, const std::string& value) {
  return u32(static_cast<uint32_t>(name.size() + 1 + value.size())) + name + "=" + value;
}
/// A record: u32 header length, header, u32 data length, data.
inline std::string record(const std::string& header, const std::string& data) {
  return u32(static_cast<uint32_t>(header.size())) + header + u32(static_cast<uint32_t>(data.size())) + data;
}

// Message types and their MD5 sums (of the .msg definitions, as ROS computes them).
const std::string kEventArrayType = "dvs_msgs/EventArray";
const std::string kEventArrayMd5 = "5e8beee5a6c107e504c2e78903c224b8";
const std::string kEventPacketType = "event_camera_msgs/EventPacket";
const std::string kEventPacketMd5 = "8a6101b351a64529ac77bd8b71074e52";
const std::string kEventArrayDefinition =
    "Header header\nuint32 height\nuint32 width\nEvent[] events\n"
    "================================================================================\n"
    "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n"
    "================================================================================\n"
    "MSG: dvs_msgs/Event\nuint16 x\nuint16 y\ntime ts\nbool polarity\n";

struct DvsEvent {
  uint16_t x, y;
  uint64_t t_ns;
  bool on;
};

/// std_msgs/Header: u32 seq, time stamp, string frame_id.
inline std::string rosHeader(uint32_t seq, uint64_t stamp_ns, const std::string& frame = "camera") {
  return u32(seq) + rosTime(stamp_ns) + rosString(frame);
}

/// dvs_msgs/EventArray: header, u32 height, u32 width, Event[] (u16 x, u16 y, time ts, bool polarity).
inline std::string eventArray(uint32_t width, uint32_t height, const std::vector<DvsEvent>& events, uint32_t seq = 0) {
  std::string m = rosHeader(seq, events.empty() ? 0 : events.front().t_ns) + u32(height) + u32(width);
  m += u32(static_cast<uint32_t>(events.size()));
  for (const DvsEvent& e : events) m += u16(e.x) + u16(e.y) + rosTime(e.t_ns) + u8(e.on ? 1 : 0);
  return m;
}

/// dvs_msgs/EventArray as rpg_dvs_ros defined it from September 2014 to October 2015: Event[] events only,
/// each event u16 x, u16 y, u64 time (µs), bool polarity.
const std::string kEventArray2014Md5 = "d2e726b2040dbc135644f4709c150a10";
inline std::string eventArray2014(const std::vector<DvsEvent>& events) {
  std::string m = u32(static_cast<uint32_t>(events.size()));
  for (const DvsEvent& e : events) m += u16(e.x) + u16(e.y) + u64(e.t_ns / 1000) + u8(e.on ? 1 : 0);
  return m;
}

/// event_camera_msgs/EventPacket: header, u32 height, u32 width, u64 seq, u64 time_base, string encoding,
/// bool is_bigendian, uint8[] events.
inline std::string eventPacket(uint32_t width, uint32_t height, const std::string& encoding, const std::string& payload,
                               uint64_t seq = 0, bool big_endian = false, uint64_t stamp_ns = 0) {
  return rosHeader(static_cast<uint32_t>(seq), stamp_ns) + u32(height) + u32(width) + u64(seq) + u64(0) +
         rosString(encoding) + u8(big_endian ? 1 : 0) + rosString(payload);
}

// Ground-truth and calibration messages (ros/common_msgs definitions, ROS1 serialization).
const std::string kPoseStampedType = "geometry_msgs/PoseStamped";
const std::string kPoseStampedMd5 = "d3812c3cbc69362b77dc0b19b345f8f5";
const std::string kTransformStampedType = "geometry_msgs/TransformStamped";
const std::string kTransformStampedMd5 = "b5764a33bfeb3588febc2682852579b0";
const std::string kOdometryType = "nav_msgs/Odometry";
const std::string kOdometryMd5 = "cd5e73d190d741a2f92e81eda573aca7";
const std::string kTfMessageType = "tf2_msgs/TFMessage";
const std::string kTfMessageMd5 = "94810edda583a504dfda3829e70d7eec";
const std::string kCameraInfoType = "sensor_msgs/CameraInfo";
const std::string kCameraInfoMd5 = "c9a58c1b0b154e0e6da7578cb991d214";

/// A float64, little-endian.
inline std::string f64(double v) {
  uint64_t bits = 0;
  static_assert(sizeof(bits) == sizeof(v), "IEEE double");
  std::memcpy(&bits, &v, sizeof(v));
  return u64(bits);
}

/// geometry_msgs/Pose: position x y z, orientation x y z w.
struct Pose {
  double px = 0, py = 0, pz = 0;
  double qx = 0, qy = 0, qz = 0, qw = 1;
};
inline std::string pose(const Pose& p) {
  return f64(p.px) + f64(p.py) + f64(p.pz) + f64(p.qx) + f64(p.qy) + f64(p.qz) + f64(p.qw);
}

/// geometry_msgs/PoseStamped: header, pose.
inline std::string poseStamped(uint64_t stamp_ns, const Pose& p, uint32_t seq = 0) {
  return rosHeader(seq, stamp_ns, "world") + pose(p);
}
/// geometry_msgs/TransformStamped: header, child_frame_id, transform (translation, rotation).
inline std::string transformStamped(uint64_t stamp_ns, const Pose& p, uint32_t seq = 0) {
  return rosHeader(seq, stamp_ns, "world") + rosString("camera") + pose(p);
}
/// One transform of a tf2_msgs/TFMessage (a geometry_msgs/TransformStamped with the given frames).
struct Transform {
  uint64_t stamp_ns = 0;
  std::string parent, child;
  Pose pose;
};
/// tf2_msgs/TFMessage: TransformStamped[] transforms.
inline std::string tfMessage(const std::vector<Transform>& transforms) {
  std::string m = u32(static_cast<uint32_t>(transforms.size()));
  for (const Transform& t : transforms) m += rosHeader(0, t.stamp_ns, t.parent) + rosString(t.child) + pose(t.pose);
  return m;
}
/// nav_msgs/Odometry: header, child_frame_id, PoseWithCovariance (pose, 36 f64), TwistWithCovariance (6 + 36 f64).
inline std::string odometry(uint64_t stamp_ns, const Pose& p, uint32_t seq = 0) {
  std::string m = rosHeader(seq, stamp_ns, "odom") + rosString("base_link") + pose(p);
  for (int i = 0; i < 36; ++i) m += f64(i == 0 ? 0.01 : 0.0);
  for (int i = 0; i < 6; ++i) m += f64(0.1 * i);
  for (int i = 0; i < 36; ++i) m += f64(0.0);
  return m;
}

/// sensor_msgs/CameraInfo: header, height, width, distortion_model, D[], K[9], R[9], P[12], binning_x,
/// binning_y, roi (x_offset, y_offset, height, width, do_rectify).
inline std::string cameraInfo(uint32_t width, uint32_t height, const std::string& model, const std::vector<double>& d,
                              double fx, double fy, double cx, double cy, uint64_t stamp_ns = 0) {
  std::string m = rosHeader(0, stamp_ns, "camera") + u32(height) + u32(width) + rosString(model);
  m += u32(static_cast<uint32_t>(d.size()));
  for (double v : d) m += f64(v);
  for (double v : {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}) m += f64(v);                    // K
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) m += f64(v);                // R
  for (double v : {fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0}) m += f64(v);    // P
  m += u32(0) + u32(0) + u32(0) + u32(0) + u32(0) + u32(0) + u8(0);                          // binning, roi
  return m;
}

struct Connection {
  uint32_t id;
  std::string topic;
  std::string type;
  std::string md5;
  std::string definition;
};

struct Message {
  uint32_t conn;
  uint64_t time_ns;
  std::string data;
};

/// A chunk: its messages, and how to compress its records ("none", or a name and a function).
struct Chunk {
  Chunk() = default;
  explicit Chunk(std::vector<Message> m, std::string c = "none",
                 std::function<std::string(const std::string&)> f = nullptr)
      : messages(std::move(m)), compression(std::move(c)), compress(std::move(f)) {}
  std::vector<Message> messages;
  std::string compression = "none";
  std::function<std::string(const std::string&)> compress;
};

inline std::string connectionRecord(const Connection& c) {
  const std::string header = field("op", u8(0x07)) + field("conn", u32(c.id)) + field("topic", c.topic);
  const std::string data = field("topic", c.topic) + field("type", c.type) + field("md5sum", c.md5) +
                           field("message_definition", c.definition);
  return record(header, data);
}

/// The whole bag: magic, bag header record (padded to 4096 bytes), per chunk a chunk record (its
/// connection records, then message-data records) followed by its index data records, then the index:
/// connection records and chunk info records.
inline std::string buildBag(const std::vector<Connection>& connections, const std::vector<Chunk>& chunks) {
  std::string body;  // everything after the bag header record
  const std::size_t body_start = 13 + 4096;
  std::string chunk_infos;
  for (const Chunk& chunk : chunks) {
    const uint64_t chunk_pos = body_start + body.size();
    std::string records;
    std::vector<uint32_t> seen;
    struct Entry {
      uint64_t time;
      uint32_t offset;
    };
    std::vector<std::pair<uint32_t, std::vector<Entry>>> index;  // per connection
    uint64_t start = UINT64_MAX, end = 0;
    for (const Message& m : chunk.messages) {
      bool known = false;
      for (uint32_t id : seen) known = known || id == m.conn;
      if (!known) {
        for (const Connection& c : connections) {
          if (c.id == m.conn) records += connectionRecord(c);
        }
        seen.push_back(m.conn);
        index.push_back({m.conn, {}});
      }
      for (auto& [id, entries] : index) {
        if (id == m.conn) entries.push_back({m.time_ns, static_cast<uint32_t>(records.size())});
      }
      start = std::min(start, m.time_ns);
      end = std::max(end, m.time_ns);
      records += record(field("op", u8(0x02)) + field("conn", u32(m.conn)) + field("time", rosTime(m.time_ns)), m.data);
    }
    const std::string stored = chunk.compress ? chunk.compress(records) : records;
    body += record(field("op", u8(0x05)) + field("compression", chunk.compression) +
                       field("size", u32(static_cast<uint32_t>(records.size()))),
                   stored);
    std::string counts;
    for (const auto& [id, entries] : index) {
      std::string data;
      for (const Entry& e : entries) data += rosTime(e.time) + u32(e.offset);
      body += record(field("op", u8(0x04)) + field("ver", u32(1)) + field("conn", u32(id)) +
                         field("count", u32(static_cast<uint32_t>(entries.size()))),
                     data);
      counts += u32(id) + u32(static_cast<uint32_t>(entries.size()));
    }
    chunk_infos += record(field("op", u8(0x06)) + field("ver", u32(1)) + field("chunk_pos", u64(chunk_pos)) +
                              field("start_time", rosTime(chunk.messages.empty() ? 0 : start)) +
                              field("end_time", rosTime(end)) +
                              field("count", u32(static_cast<uint32_t>(index.size()))),
                          counts);
  }
  const uint64_t index_pos = body_start + body.size();
  for (const Connection& c : connections) body += connectionRecord(c);
  body += chunk_infos;
  const std::string header = field("op", u8(0x03)) + field("index_pos", u64(index_pos)) +
                             field("conn_count", u32(static_cast<uint32_t>(connections.size()))) +
                             field("chunk_count", u32(static_cast<uint32_t>(chunks.size())));
  // The bag header record is padded with spaces to 4096 bytes, so it can be rewritten in place.
  const std::string bag_header = record(header, std::string(4096 - 8 - header.size(), ' '));
  return "#ROSBAG V2.0\n" + bag_header + body;
}

}  // namespace asynevo::testing::bag
