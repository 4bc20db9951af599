// Writes tests/data/rosbag/dvs_lz4.bag and dvs_bz2.bag with the ROS library's own bag writer
// (librosbag-storage-dev), so the reader's tests also read chunks compressed the way ROS compresses them.
// Not part of the build (AsynEVO does not depend on the ROS libraries); how to run it:
// tests/data/SOURCES.md. The events match tests/io/rosbag_reader_test.cpp: 350 events, t = 1.6e9 s + i µs,
// pixel (i % 240, i % 180), polarity ON for even i, in messages of 100, 0 and 250 events on /dvs/events,
// with /dvs/imu messages of 300 bytes between them.
#include <rosbag/bag.h>

#include <cstdint>
#include <string>
#include <vector>

// A message whose bytes are already ROS1-serialized, with the type, MD5 sum and definition it stands for.
struct RawMessage {
  std::string type, md5, definition;
  std::vector<uint8_t> bytes;
};

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<RawMessage> {
  static const char* value(const RawMessage& m) { return m.md5.c_str(); }
};
template <>
struct DataType<RawMessage> {
  static const char* value(const RawMessage& m) { return m.type.c_str(); }
};
template <>
struct Definition<RawMessage> {
  static const char* value(const RawMessage& m) { return m.definition.c_str(); }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<RawMessage> {
  template <typename Stream>
  static void write(Stream& stream, const RawMessage& m) {
    std::memcpy(stream.advance(m.bytes.size()), m.bytes.data(), m.bytes.size());
  }
  static uint32_t serializedLength(const RawMessage& m) { return m.bytes.size(); }
};
}  // namespace serialization
}  // namespace ros

namespace {

const uint64_t kT0 = 1600000000ull * 1000000000ull;

void put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void put16(std::vector<uint8_t>& b, uint32_t v) {
  b.push_back(static_cast<uint8_t>(v));
  b.push_back(static_cast<uint8_t>(v >> 8));
}
void putTime(std::vector<uint8_t>& b, uint64_t t) {
  put32(b, static_cast<uint32_t>(t / 1000000000));
  put32(b, static_cast<uint32_t>(t % 1000000000));
}

RawMessage eventArray(int first, int count) {
  RawMessage m{"dvs_msgs/EventArray", "5e8beee5a6c107e504c2e78903c224b8",
               "Header header\nuint32 height\nuint32 width\nEvent[] events\n"
               "================================================================================\n"
               "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n"
               "================================================================================\n"
               "MSG: dvs_msgs/Event\nuint16 x\nuint16 y\ntime ts\nbool polarity\n",
               {}};
  auto& b = m.bytes;
  put32(b, 0);
  putTime(b, count > 0 ? kT0 + uint64_t(first) * 1000 : 0);
  put32(b, 6);
  for (char c : std::string("camera")) b.push_back(static_cast<uint8_t>(c));
  put32(b, 180);
  put32(b, 240);
  put32(b, static_cast<uint32_t>(count));
  for (int i = first; i < first + count; ++i) {
    put16(b, i % 240);
    put16(b, i % 180);
    putTime(b, kT0 + uint64_t(i) * 1000);
    b.push_back(i % 2 == 0 ? 1 : 0);
  }
  return m;
}

RawMessage imu() {
  return {"sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2", "(not needed)", std::vector<uint8_t>(300, 'i')};
}

void write(const std::string& path, rosbag::CompressionType compression) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  auto t = [](uint64_t ns) { return ros::Time(static_cast<uint32_t>(ns / 1000000000), ns % 1000000000); };
  bag.write("/dvs/events", t(kT0), eventArray(0, 100));
  bag.write("/dvs/imu", t(kT0), imu());
  bag.write("/dvs/events", t(kT0 + 100000), eventArray(100, 0));
  bag.write("/dvs/imu", t(kT0 + 5000), imu());
  bag.write("/dvs/events", t(kT0 + 100000), eventArray(100, 250));
  bag.write("/dvs/imu", t(kT0 + 10000), imu());
  bag.close();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  write(dir + "/dvs_lz4.bag", rosbag::compression::LZ4);
  write(dir + "/dvs_bz2.bag", rosbag::compression::BZ2);
  return 0;
}
