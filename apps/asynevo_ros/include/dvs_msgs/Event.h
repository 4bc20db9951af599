#pragma once
// dvs_msgs/Event for roscpp, written for AsynEVO (dvs_msgs is not packaged by Debian). Wire-compatible with
// the message of rpg_dvs_ros (github.com/uzh-rpg/rpg_dvs_ros, dvs_msgs/msg/Event.msg):
//   uint16 x
//   uint16 y
//   time ts
//   bool polarity
// 13 bytes on the wire. The MD5 sum is ROS's checksum of that definition (without comments),
// md5("uint16 x\nuint16 y\ntime ts\nbool polarity"); docs/reference/formats_rosbag.md has the same sums.

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <ros/time.h>

#include <boost/shared_ptr.hpp>
#include <cstdint>

namespace dvs_msgs {

struct Event {
  uint16_t x = 0;
  uint16_t y = 0;
  ros::Time ts;
  uint8_t polarity = 0;  ///< ROS bool: 1 ON, 0 OFF

  using Ptr = boost::shared_ptr<Event>;
  using ConstPtr = boost::shared_ptr<const Event>;
};

}  // namespace dvs_msgs

namespace ros {
namespace message_traits {

template <>
struct MD5Sum<dvs_msgs::Event> {
  static const char* value() { return "40d339b261445b8ce9a6fef01267cd5d"; }
  static const char* value(const dvs_msgs::Event&) { return value(); }
};
template <>
struct DataType<dvs_msgs::Event> {
  static const char* value() { return "dvs_msgs/Event"; }
  static const char* value(const dvs_msgs::Event&) { return value(); }
};
template <>
struct Definition<dvs_msgs::Event> {
  static const char* value() {
    return "# A DVS event\n"
           "uint16 x\n"
           "uint16 y\n"
           "time ts\n"
           "bool polarity\n";
  }
  static const char* value(const dvs_msgs::Event&) { return value(); }
};
template <>
struct IsFixedSize<dvs_msgs::Event> : TrueType {};
template <>
struct IsSimple<dvs_msgs::Event> : FalseType {};  // 13 bytes on the wire, padded in memory

}  // namespace message_traits

namespace serialization {

template <>
struct Serializer<dvs_msgs::Event> {
  template <typename Stream, typename M>
  inline static void allInOne(Stream& stream, M& m) {
    stream.next(m.x);
    stream.next(m.y);
    stream.next(m.ts);
    stream.next(m.polarity);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};

}  // namespace serialization
}  // namespace ros
