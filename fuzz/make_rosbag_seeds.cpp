// Writes the ROS bag seeds of fuzz/corpus/rosbag_events and fuzz/corpus/rosbag_topics with the test suite's specification-built
// fixture (tests/io/rosbag_fixture.hpp). Not part of the build; run once:
//   g++ -std=c++17 -I tests fuzz/make_rosbag_seeds.cpp -llz4 -lbz2 -o /tmp/rosbag_seeds
//   /tmp/rosbag_seeds fuzz/corpus

#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "io/chunk_compression.hpp"
#include "io/rosbag_fixture.hpp"

namespace bag = asynevo::testing::bag;

namespace {

const bag::Connection kDvs{0, "/dvs/events", bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
const bag::Connection kImu{1, "/dvs/imu", "sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2", "-"};
const bag::Connection kPackets{2, "/event_camera/events", bag::kEventPacketType, bag::kEventPacketMd5, "-"};

std::string dvs(const std::string& compression, std::string (*compress)(const std::string&)) {
  std::vector<bag::DvsEvent> a, b;
  for (int i = 0; i < 6; ++i) a.push_back({uint16_t(i * 5), uint16_t(i * 3), 1'000'000'000ull + i * 1000ull, i % 2 == 0});
  for (int i = 6; i < 9; ++i) b.push_back({uint16_t(i * 5), uint16_t(i * 3), 1'000'000'000ull + i * 1000ull, i % 2 == 0});
  bag::Chunk c1{{{0, 1'000'000'000ull, bag::eventArray(64, 32, a)}, {1, 1'000'000'000ull, std::string(20, 'i')}},
                compression, nullptr};
  bag::Chunk c2{{{0, 1'000'006'000ull, bag::eventArray(64, 32, b)}}, compression, nullptr};
  if (compress != nullptr) c1.compress = c2.compress = compress;
  return bag::buildBag({kDvs, kImu}, {c1, c2});
}

std::string packets() {
  auto w = [](std::initializer_list<uint32_t> words) {
    std::string s;
    for (uint32_t x : words) s += bag::u16(x);
    return s;
  };
  bag::Chunk chunk{{{2, 1, bag::eventPacket(64, 32, "evt3", w({0x8001, 0x6005, 0x0007}))},
                    {2, 2, bag::eventPacket(64, 32, "evt3", w({0x2803, 0x300A, 0x4805, 0x6009, 0x2001, 0xA001}), 1)}}};
  return bag::buildBag({kPackets}, {chunk});
}

const bag::Connection kPose{3, "/pose", bag::kPoseStampedType, bag::kPoseStampedMd5, "-"};
const bag::Connection kTf{4, "/tf_cam", bag::kTransformStampedType, bag::kTransformStampedMd5, "-"};
const bag::Connection kOdom{5, "/odom", bag::kOdometryType, bag::kOdometryMd5, "-"};
const bag::Connection kInfo{6, "/camera_info", bag::kCameraInfoType, bag::kCameraInfoMd5, "-"};
const bag::Connection kTfTopic{7, "/tf", bag::kTfMessageType, bag::kTfMessageMd5, "-"};

/// Events, a pose topic of `pose`'s type (3 messages) and a CameraInfo of `model`.
std::string topics(const bag::Connection& pose, const std::string& model, const std::vector<double>& d,
                   const std::string& compression = "none", std::string (*compress)(const std::string&) = nullptr) {
  std::vector<bag::Message> m;
  m.push_back({6, 1'000'000'000ull, bag::cameraInfo(64, 32, model, d, 50, 51, 32, 16)});
  m.push_back({0, 1'000'000'000ull, bag::eventArray(64, 32, {{1, 2, 1'000'000'000ull, true}})});
  for (int i = 0; i < 3; ++i) {
    bag::Pose p;
    p.px = 0.1 * i;
    p.qz = 0.1 * i;
    p.qw = 1;
    const uint64_t t = 1'000'000'000ull + i * 10'000'000ull;
    const std::string data = pose.id == 3   ? bag::poseStamped(t, p)
                             : pose.id == 4 ? bag::transformStamped(t, p)
                             : pose.id == 7 ? bag::tfMessage({{t, "world", "cam", p}, {t, "odom", "base", p}})
                                            : bag::odometry(t, p);
    m.push_back({pose.id, t, data});
  }
  bag::Chunk chunk{m, compression, nullptr};
  if (compress != nullptr) chunk.compress = compress;
  return bag::buildBag({kDvs, pose, kInfo}, {chunk});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/rosbag_events/";
  const std::pair<const char*, std::string> seeds[] = {
      {"seed_none.bag", dvs("none", nullptr)},
      {"seed_lz4.bag", dvs("lz4", bag::lz4)},
      {"seed_bz2.bag", dvs("bz2", bag::bz2)},
      {"seed_evt3_packets.bag", packets()},
  };
  for (const auto& [name, bytes] : seeds) std::ofstream(dir + name, std::ios::binary) << bytes;
  const std::string cut = dvs("lz4", bag::lz4);
  std::ofstream(dir + "seed_truncated.bag", std::ios::binary) << cut.substr(0, cut.size() - 7);

  const std::string topics_dir = std::string(argv[1]) + "/rosbag_topics/";
  const std::pair<const char*, std::string> topic_seeds[] = {
      {"seed_posestamped_radtan.bag", topics(kPose, "plumb_bob", {-0.3, 0.1, 0.001, 0.002, 0.01})},
      {"seed_transform_equidistant.bag", topics(kTf, "equidistant", {0.1, 0.01, 0.001, 0.0001})},
      {"seed_odometry_pinhole_lz4.bag", topics(kOdom, "plumb_bob", {}, "lz4", bag::lz4)},
      {"seed_tf_two_frames.bag", topics(kTfTopic, "plumb_bob", {})},
  };
  for (const auto& [name, bytes] : topic_seeds) std::ofstream(topics_dir + name, std::ios::binary) << bytes;
  return 0;
}
