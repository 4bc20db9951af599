// Test helper of the ROS node tests (test_ros_node.py): publishes dvs_msgs/EventArray messages.
//   event_publisher play DATASET [SPEED] [MESSAGE_MS]   the dataset's events (any format asynevo reads),
//       in messages of MESSAGE_MS of event time (default 5), paced at SPEED x real time (default 1; 0 = as
//       fast as possible), stamped like a driver (header.stamp = the first event's time, 240x180 or the
//       reader's size)
//   event_publisher malformed                            one message of each malformed kind the node must
//       skip and count, between two valid ones (the sequence: malformed() below)
// Topic "events" (remap with events:=/name). Waits up to 10 s for a subscriber, prints what it sent.
#include <ros/ros.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "dvs_msgs/EventArray.h"

namespace {

// A message whose bytes are written as given, advertised as dvs_msgs/EventArray: a message cut short.
struct RawEventArray {
  std::vector<uint8_t> bytes;
};

}  // namespace

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<RawEventArray> {
  static const char* value() { return MD5Sum<dvs_msgs::EventArray>::value(); }
  static const char* value(const RawEventArray&) { return value(); }
};
template <>
struct DataType<RawEventArray> {
  static const char* value() { return DataType<dvs_msgs::EventArray>::value(); }
  static const char* value(const RawEventArray&) { return value(); }
};
template <>
struct Definition<RawEventArray> {
  static const char* value() { return Definition<dvs_msgs::EventArray>::value(); }
  static const char* value(const RawEventArray&) { return value(); }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<RawEventArray> {
  template <typename Stream>
  static void write(Stream& stream, const RawEventArray& m) {
    std::memcpy(stream.advance(static_cast<uint32_t>(m.bytes.size())), m.bytes.data(), m.bytes.size());
  }
  static uint32_t serializedLength(const RawEventArray& m) { return static_cast<uint32_t>(m.bytes.size()); }
};
}  // namespace serialization
}  // namespace ros

namespace {

ros::Time rosTime(int64_t t_ns) {
  ros::Time t;
  t.sec = static_cast<uint32_t>(t_ns / 1000000000);
  t.nsec = static_cast<uint32_t>(t_ns % 1000000000);
  return t;
}

dvs_msgs::EventArray message(const std::vector<asynevo::Event>& events, std::size_t begin, std::size_t end,
                             uint32_t width, uint32_t height, uint32_t seq) {
  dvs_msgs::EventArray m;
  m.header.seq = seq;
  m.header.frame_id = "dvs";
  m.width = width;
  m.height = height;
  m.events.resize(end - begin);
  for (std::size_t i = begin; i < end; ++i) {
    dvs_msgs::Event& e = m.events[i - begin];
    e.x = events[i].x;
    e.y = events[i].y;
    e.ts = rosTime(events[i].t_ns);
    e.polarity = events[i].polarity > 0 ? 1 : 0;
  }
  if (!m.events.empty()) m.header.stamp = m.events.front().ts;
  return m;
}

bool waitForSubscriber(const ros::Publisher& pub) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (pub.getNumSubscribers() == 0) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return false;
    ros::WallDuration(0.01).sleep();
  }
  ros::WallDuration(0.2).sleep();  // the subscriber's connection is ready on both sides
  return true;
}

int play(ros::Publisher& pub, const std::string& dataset, double speed, double message_ms) {
  const asynevo::DatasetFiles files = asynevo::resolveDataset(dataset);
  const auto reader = asynevo::openEventReader(files.events);
  std::vector<asynevo::Event> events;
  asynevo::EventPacket packet;
  while (reader->read(packet)) events.insert(events.end(), packet.events.begin(), packet.events.end());
  if (events.empty()) {
    std::fprintf(stderr, "event_publisher: %s has no events\n", dataset.c_str());
    return 1;
  }
  const uint32_t width = reader->info().width > 0 ? static_cast<uint32_t>(reader->info().width) : 240;
  const uint32_t height = reader->info().height > 0 ? static_cast<uint32_t>(reader->info().height) : 180;
  if (!waitForSubscriber(pub)) {
    std::fprintf(stderr, "event_publisher: no subscriber on %s within 10 s\n", pub.getTopic().c_str());
    return 1;
  }
  const int64_t period_ns = static_cast<int64_t>(message_ms * 1e6);
  const int64_t t0 = events.front().t_ns;
  const ros::WallTime wall0 = ros::WallTime::now();
  std::size_t begin = 0, messages = 0;
  while (begin < events.size() && ros::ok()) {
    const int64_t end_t = events[begin].t_ns - (events[begin].t_ns - t0) % period_ns + period_ns;
    std::size_t end = begin;
    while (end < events.size() && events[end].t_ns < end_t) ++end;
    if (speed > 0) {  // publish when the message's last event is due
      const ros::WallTime due = wall0 + ros::WallDuration((events[end - 1].t_ns - t0) * 1e-9 / speed);
      const ros::WallDuration wait = due - ros::WallTime::now();
      if (wait > ros::WallDuration(0)) wait.sleep();
    }
    pub.publish(message(events, begin, end, width, height, static_cast<uint32_t>(messages)));
    ++messages;
    begin = end;
  }
  const double wall_s = (ros::WallTime::now() - wall0).toSec();
  ros::WallDuration(0.5).sleep();  // let the queue drain before the connection closes
  std::printf("published %zu events in %zu messages over %.3f s (event span %.3f s)\n", events.size(),
              messages, wall_s, (events.back().t_ns - t0) * 1e-9);
  return 0;
}

// The malformed sequence: valid, then one of each kind the node must skip, then valid again.
int malformed(ros::Publisher& pub) {
  if (!waitForSubscriber(pub)) {
    std::fprintf(stderr, "event_publisher: no subscriber on %s within 10 s\n", pub.getTopic().c_str());
    return 1;
  }
  const int64_t t0 = 1600000000LL * 1000000000LL;
  std::vector<asynevo::Event> events(200);
  for (int i = 0; i < 200; ++i)
    events[static_cast<std::size_t>(i)] =
        asynevo::Event{t0 + i * 1000, static_cast<uint16_t>(10 + i % 200),
                       static_cast<uint16_t>(20 + i % 150), static_cast<int8_t>(i % 2 ? 1 : -1)};
  uint32_t seq = 0;
  std::vector<std::string> sent;
  auto send = [&](const dvs_msgs::EventArray& m, const char* what) {
    pub.publish(m);
    sent.push_back(what);
    ros::WallDuration(0.02).sleep();
  };
  send(message(events, 0, 100, 240, 180, seq++), "valid");
  dvs_msgs::EventArray m = message(events, 100, 110, 240, 180, seq++);
  m.events[5].x = 240;
  send(m, "out_of_sensor");
  send(message(events, 50, 60, 240, 180, seq++), "time_backwards");
  send(message(events, 100, 100, 240, 180, seq++), "empty");
  send(message(events, 100, 110, 346, 260, seq++), "size_mismatch");
  m = message(events, 100, 110, 240, 180, seq++);
  std::swap(m.events[2].ts, m.events[7].ts);
  send(m, "unsorted");
  m = message(events, 100, 110, 240, 180, seq++);
  m.events[3].ts.nsec = 1500000000u;
  send(m, "bad_time");
  // decode_error: a valid message's bytes, cut 20 bytes short (its event count promises more than it holds).
  const dvs_msgs::EventArray whole = message(events, 100, 110, 240, 180, seq++);
  RawEventArray raw;
  raw.bytes.resize(ros::serialization::serializationLength(whole));
  ros::serialization::OStream out(raw.bytes.data(), static_cast<uint32_t>(raw.bytes.size()));
  ros::serialization::serialize(out, whole);
  raw.bytes.resize(raw.bytes.size() - 20);
  pub.publish(raw);
  sent.push_back("decode_error");
  ros::WallDuration(0.02).sleep();
  send(message(events, 100, 200, 0, 0, seq++), "valid (no size stated)");
  ros::WallDuration(0.5).sleep();
  std::printf("published %zu messages:", sent.size());
  for (const std::string& s : sent) std::printf(" %s;", s.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "event_publisher", ros::init_options::AnonymousName);
  const std::vector<std::string> args(argv + 1, argv + argc);  // ROS remappings are removed by ros::init
  if (args.empty() || (args[0] == "play" && args.size() < 2) ||
      (args[0] != "play" && args[0] != "malformed")) {
    std::fprintf(stderr,
                 "usage: event_publisher play DATASET [SPEED] [MESSAGE_MS] | event_publisher malformed\n");
    return 2;
  }
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<dvs_msgs::EventArray>("events", 100000);
  try {
    if (args[0] == "malformed") return malformed(pub);
    const double speed = args.size() > 2 ? std::atof(args[2].c_str()) : 1.0;
    const double message_ms = args.size() > 3 ? std::atof(args[3].c_str()) : 5.0;
    if (message_ms <= 0) {
      std::fprintf(stderr, "event_publisher: MESSAGE_MS must be positive\n");
      return 2;
    }
    return play(pub, args[1], speed, message_ms);
  } catch (const asynevo::Error& e) {
    std::fprintf(stderr, "event_publisher: %s\n", e.what());
    return 1;
  }
}
