#pragma once
// dvs_msgs/EventArray for roscpp, written for AsynEVO (dvs_msgs is not packaged by Debian). Wire-compatible
// with the message of rpg_dvs_ros (github.com/uzh-rpg/rpg_dvs_ros, dvs_msgs/msg/EventArray.msg, the revision
// since October 2015 that DAVIS drivers, ESIM and the ECD/MVSEC bags use):
//   Header header
//   uint32 height         # image height, that is, number of rows
//   uint32 width          # image width, that is, number of columns
//   Event[] events
// The MD5 sum is ROS's checksum md5("<Header md5> header\nuint32 height\nuint32 width\n<Event md5> events"),
// the sum asynevo's bag reader accepts (docs/reference/formats_rosbag.md).
//
// Reading is defensive: a message whose event count exceeds its bytes, or that is cut short, is not thrown
// out inside roscpp (where a node cannot count it) but delivered with `decode_error` set and no events, so
// the node logs and counts it. `decode_error` is not part of the message on the wire.

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <std_msgs/Header.h>

#include <boost/shared_ptr.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "dvs_msgs/Event.h"

namespace dvs_msgs {

struct EventArray {
  std_msgs::Header header;
  uint32_t height = 0;
  uint32_t width = 0;
  std::vector<Event> events;

  std::string decode_error;  ///< not serialized: set when the received bytes were not a valid message

  using Ptr = boost::shared_ptr<EventArray>;
  using ConstPtr = boost::shared_ptr<const EventArray>;
};

/// Bytes of one event on the wire: uint16 x, uint16 y, time ts (2 x uint32), bool polarity.
constexpr uint32_t kEventWireBytes = 13;

}  // namespace dvs_msgs

namespace ros {
namespace message_traits {

template <>
struct MD5Sum<dvs_msgs::EventArray> {
  static const char* value() { return "5e8beee5a6c107e504c2e78903c224b8"; }
  static const char* value(const dvs_msgs::EventArray&) { return value(); }
};
template <>
struct DataType<dvs_msgs::EventArray> {
  static const char* value() { return "dvs_msgs/EventArray"; }
  static const char* value(const dvs_msgs::EventArray&) { return value(); }
};
template <>
struct Definition<dvs_msgs::EventArray> {
  static const char* value() {
    return "# This message contains an array of events\n"
           "# (0, 0) is at top-left corner of image\n"
           "#\n"
           "\n"
           "Header header\n"
           "\n"
           "uint32 height         # image height, that is, number of rows\n"
           "uint32 width          # image width, that is, number of columns\n"
           "\n"
           "# an array of events\n"
           "Event[] events\n"
           "\n"
           "================================================================================\n"
           "MSG: std_msgs/Header\n"
           "uint32 seq\n"
           "time stamp\n"
           "string frame_id\n"
           "\n"
           "================================================================================\n"
           "MSG: dvs_msgs/Event\n"
           "# A DVS event\n"
           "uint16 x\n"
           "uint16 y\n"
           "time ts\n"
           "bool polarity\n";
  }
  static const char* value(const dvs_msgs::EventArray&) { return value(); }
};
template <>
struct HasHeader<dvs_msgs::EventArray> : TrueType {};
template <>
struct IsFixedSize<dvs_msgs::EventArray> : FalseType {};

}  // namespace message_traits

namespace serialization {

template <>
struct Serializer<dvs_msgs::EventArray> {
  template <typename Stream>
  inline static void write(Stream& stream, const dvs_msgs::EventArray& m) {
    stream.next(m.header);
    stream.next(m.height);
    stream.next(m.width);
    stream.next(m.events);
  }

  template <typename Stream>
  inline static void read(Stream& stream, dvs_msgs::EventArray& m) {
    m.events.clear();
    m.decode_error.clear();
    try {
      stream.next(m.header);
      stream.next(m.height);
      stream.next(m.width);
      uint32_t count = 0;
      stream.next(count);
      const uint64_t need = uint64_t{count} * dvs_msgs::kEventWireBytes;
      if (need > stream.getLength()) {
        m.decode_error = "the message states " + std::to_string(count) + " events (" + std::to_string(need) +
                         " bytes) but has " + std::to_string(stream.getLength()) + " bytes left";
        return;
      }
      m.events.resize(count);
      for (dvs_msgs::Event& e : m.events) stream.next(e);
      if (stream.getLength() != 0)
        m.decode_error = std::to_string(stream.getLength()) + " bytes after the last event";
    } catch (const ros::serialization::StreamOverrunException& e) {
      m.events.clear();
      m.decode_error = std::string("the message is cut short: ") + e.what();
    }
  }

  inline static uint32_t serializedLength(const dvs_msgs::EventArray& m) {
    return serializationLength(m.header) + 4 + 4 + 4 +
           static_cast<uint32_t>(m.events.size()) * dvs_msgs::kEventWireBytes;
  }
};

}  // namespace serialization
}  // namespace ros
