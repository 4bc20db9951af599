// dvs_msgs/EventArray as written by apps/asynevo_ros/include/dvs_msgs: the bytes on the wire (the layout
// of rpg_dvs_ros's message, as docs/reference/formats_rosbag.md describes and our bag reader decodes), the
// defensive decoding of bad bytes, and the node's message checks (event_array_check.hpp).
#include "event_array_check.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "dvs_msgs/EventArray.h"

namespace asynevo::ros_node {
namespace {

void put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void put16(std::vector<uint8_t>& b, uint32_t v) {
  b.push_back(static_cast<uint8_t>(v));
  b.push_back(static_cast<uint8_t>(v >> 8));
}

dvs_msgs::EventArray sample() {
  dvs_msgs::EventArray m;
  m.header.seq = 7;
  m.header.stamp = ros::Time(1600000000, 5);
  m.header.frame_id = "dvs";
  m.width = 240;
  m.height = 180;
  m.events.resize(2);
  m.events[0].x = 3;
  m.events[0].y = 4;
  m.events[0].ts = ros::Time(1600000000, 1000);
  m.events[0].polarity = 1;
  m.events[1].x = 239;
  m.events[1].y = 179;
  m.events[1].ts = ros::Time(1600000000, 2000);
  m.events[1].polarity = 0;
  return m;
}

std::vector<uint8_t> serialize(const dvs_msgs::EventArray& m) {
  std::vector<uint8_t> bytes(ros::serialization::serializationLength(m));
  ros::serialization::OStream out(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::serialize(out, m);
  return bytes;
}

dvs_msgs::EventArray deserialize(std::vector<uint8_t> bytes) {
  dvs_msgs::EventArray m;
  ros::serialization::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, m);
  return m;
}

TEST(DvsMessages, TraitsAreThoseOfRpgDvsRos) {
  EXPECT_STREQ(ros::message_traits::md5sum<dvs_msgs::EventArray>(), "5e8beee5a6c107e504c2e78903c224b8");
  EXPECT_STREQ(ros::message_traits::datatype<dvs_msgs::EventArray>(), "dvs_msgs/EventArray");
  EXPECT_STREQ(ros::message_traits::md5sum<dvs_msgs::Event>(), "40d339b261445b8ce9a6fef01267cd5d");
  EXPECT_STREQ(ros::message_traits::datatype<dvs_msgs::Event>(), "dvs_msgs/Event");
}

TEST(DvsMessages, WireLayoutIsHeaderSizeThenThirteenBytesPerEvent) {
  std::vector<uint8_t> expected;
  put32(expected, 7);  // header: seq, stamp, frame_id
  put32(expected, 1600000000);
  put32(expected, 5);
  put32(expected, 3);
  for (char c : std::string("dvs")) expected.push_back(static_cast<uint8_t>(c));
  put32(expected, 180);  // height, then width
  put32(expected, 240);
  put32(expected, 2);
  for (uint32_t v : {3u, 4u}) put16(expected, v);
  put32(expected, 1600000000);
  put32(expected, 1000);
  expected.push_back(1);
  for (uint32_t v : {239u, 179u}) put16(expected, v);
  put32(expected, 1600000000);
  put32(expected, 2000);
  expected.push_back(0);
  EXPECT_EQ(serialize(sample()), expected);

  const dvs_msgs::EventArray back = deserialize(expected);
  EXPECT_TRUE(back.decode_error.empty()) << back.decode_error;
  EXPECT_EQ(back.header.frame_id, "dvs");
  EXPECT_EQ(back.width, 240u);
  EXPECT_EQ(back.height, 180u);
  ASSERT_EQ(back.events.size(), 2u);
  EXPECT_EQ(back.events[1].x, 239);
  EXPECT_EQ(back.events[1].ts.nsec, 2000u);
  EXPECT_EQ(back.events[0].polarity, 1);
}

TEST(DvsMessages, BadBytesAreReportedNotThrown) {
  std::vector<uint8_t> bytes = serialize(sample());
  std::vector<uint8_t> cut(bytes.begin(), bytes.end() - 5);  // inside the last event
  dvs_msgs::EventArray m = deserialize(cut);
  EXPECT_NE(m.decode_error.find("states 2 events"), std::string::npos) << m.decode_error;
  EXPECT_TRUE(m.events.empty());

  cut.assign(bytes.begin(), bytes.begin() + 10);  // inside the header's frame_id
  m = deserialize(cut);
  EXPECT_NE(m.decode_error.find("cut short"), std::string::npos) << m.decode_error;

  // An event count of 2^32 - 1 with 26 bytes of events (the count follows the 19-byte header, height, width).
  std::vector<uint8_t> huge(bytes.begin(), bytes.begin() + 27);
  put32(huge, 0xffffffffu);
  huge.insert(huge.end(), bytes.begin() + 31, bytes.end());
  m = deserialize(huge);
  EXPECT_NE(m.decode_error.find("4294967295 events"), std::string::npos) << m.decode_error;
  EXPECT_TRUE(m.events.empty());

  bytes.push_back(0);
  m = deserialize(bytes);
  EXPECT_NE(m.decode_error.find("1 bytes after the last event"), std::string::npos) << m.decode_error;
}

StreamState sensor240() {
  StreamState s;
  s.width = 240;
  s.height = 180;
  return s;
}

TEST(CheckEventArray, ConvertsAValidMessage) {
  const CheckResult r = checkEventArray(sample(), sensor240());
  ASSERT_EQ(r.reason, SkipReason::kNone) << r.message;
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0].t_ns, 1600000000LL * 1000000000LL + 1000);
  EXPECT_EQ(r.events[0].polarity, 1);
  EXPECT_EQ(r.events[1].polarity, -1);
  EXPECT_EQ(r.events[1].x, 239);
}

TEST(CheckEventArray, SkipsEachMalformedKindWithItsReason) {
  dvs_msgs::EventArray m = sample();
  m.events[1].x = 240;
  CheckResult r = checkEventArray(m, sensor240());
  EXPECT_EQ(r.reason, SkipReason::kOutOfSensor);
  EXPECT_EQ(r.message, "event 1 at pixel (240, 179) is outside the 240x180 sensor");
  EXPECT_TRUE(r.events.empty());

  m = sample();
  m.width = 346;
  m.height = 260;
  EXPECT_EQ(checkEventArray(m, sensor240()).reason, SkipReason::kSizeMismatch);
  m.width = m.height = 0;  // no size stated: accepted
  EXPECT_EQ(checkEventArray(m, sensor240()).reason, SkipReason::kNone);

  m = sample();
  m.events.clear();
  EXPECT_EQ(checkEventArray(m, sensor240()).reason, SkipReason::kEmpty);

  m = sample();
  std::swap(m.events[0].ts, m.events[1].ts);
  r = checkEventArray(m, sensor240());
  EXPECT_EQ(r.reason, SkipReason::kUnsorted);
  EXPECT_NE(r.message.find("event 1"), std::string::npos) << r.message;

  m = sample();
  m.events[0].ts.nsec = 1000000000u;
  EXPECT_EQ(checkEventArray(m, sensor240()).reason, SkipReason::kBadTime);

  m = sample();
  m.decode_error = "cut short";
  EXPECT_EQ(checkEventArray(m, sensor240()).reason, SkipReason::kDecodeError);
}

TEST(CheckEventArray, TimeMustContinueFromTheLastAcceptedEvent) {
  StreamState s = sensor240();
  s.has_last = true;
  s.last_t_ns = 1600000000LL * 1000000000LL + 1000;  // equal to the first event: accepted
  EXPECT_EQ(checkEventArray(sample(), s).reason, SkipReason::kNone);
  s.last_t_ns += 1;
  const CheckResult r = checkEventArray(sample(), s);
  EXPECT_EQ(r.reason, SkipReason::kTimeBackwards);
  EXPECT_NE(r.message.find("earlier than the last accepted"), std::string::npos) << r.message;
  EXPECT_STREQ(skipReasonName(r.reason), "time_backwards");
}

TEST(CheckEventArray, SmallStepsBackAreClampedWithinTheConfiguredTolerance) {
  StreamState s = sensor240();
  s.max_time_reversal_ns = 500;
  dvs_msgs::EventArray m = sample();
  m.events[1].ts = ros::Time(1600000000, 600);  // 400 ns before event 0: clamped to its time
  CheckResult r = checkEventArray(m, s);
  ASSERT_EQ(r.reason, SkipReason::kNone) << r.message;
  EXPECT_EQ(r.clamped, 1u);
  EXPECT_EQ(r.events[1].t_ns, r.events[0].t_ns);
  m.events[1].ts = ros::Time(1600000000, 499);  // 501 ns before: beyond the tolerance
  EXPECT_EQ(checkEventArray(m, s).reason, SkipReason::kUnsorted);
  s.has_last = true;
  s.last_t_ns = 1600000000LL * 1000000000LL + 1500;  // the message starts 500 ns earlier: clamped
  r = checkEventArray(sample(), s);
  ASSERT_EQ(r.reason, SkipReason::kNone) << r.message;
  EXPECT_EQ(r.events[0].t_ns, s.last_t_ns);
  EXPECT_EQ(r.clamped, 1u);
}

}  // namespace
}  // namespace asynevo::ros_node
