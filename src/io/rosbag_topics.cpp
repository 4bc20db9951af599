// Ground truth and calibration topics of ROS1 bags; see include/asynevo/io/rosbag_topics.hpp.
//
// Message layouts, from the ROS1 message definitions (ros/common_msgs and ros/std_msgs, noetic) and
// ROS1 serialization (little-endian; time = u32 sec + u32 nsec; string and T[] = u32 count + elements;
// T[N] = N elements, no count):
//
//   std_msgs/Header              u32 seq, time stamp, string frame_id
//   geometry_msgs/Pose           Point position (3 f64 x y z), Quaternion orientation (4 f64 x y z w)
//   geometry_msgs/PoseStamped    Header header, Pose pose
//   geometry_msgs/TransformStamped  Header header, string child_frame_id,
//                                Transform transform (Vector3 translation 3 f64, Quaternion rotation 4 f64)
//   nav_msgs/Odometry            Header header, string child_frame_id,
//                                PoseWithCovariance pose (Pose, float64[36] covariance),
//                                TwistWithCovariance twist (Twist 6 f64, float64[36] covariance)
//   tf2_msgs/TFMessage           TransformStamped[] transforms (also tf/tfMessage, the same definition)
//   sensor_msgs/CameraInfo       Header header, u32 height, u32 width, string distortion_model,
//                                float64[] D, float64[9] K, float64[9] R, float64[12] P,
//                                u32 binning_x, u32 binning_y,
//                                RegionOfInterest roi (u32 x_offset, y_offset, height, width, bool do_rectify)
//
// MD5 sums: the checksums ROS computes from these definitions, as `rosbag info` and the generated
// message headers print them.
#include "asynevo/io/rosbag_topics.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <initializer_list>
#include <map>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/io/camera_info.hpp"
#include "asynevo/io/file_handle.hpp"
#include "rosbag_reader.hpp"

namespace asynevo {

namespace {

constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kPoseStampedMd5 = "d3812c3cbc69362b77dc0b19b345f8f5";
constexpr const char* kTransformStamped = "geometry_msgs/TransformStamped";
constexpr const char* kTransformStampedMd5 = "b5764a33bfeb3588febc2682852579b0";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kOdometryMd5 = "cd5e73d190d741a2f92e81eda573aca7";
constexpr const char* kTfMessage = "tf2_msgs/TFMessage";
constexpr const char* kTfMessageOld = "tf/tfMessage";  // ROS1's first tf package, same definition and sum
constexpr const char* kTfMessageMd5 = "94810edda583a504dfda3829e70d7eec";
constexpr const char* kEventArray = "dvs_msgs/EventArray";
constexpr const char* kEventPacket = "event_camera_msgs/EventPacket";
constexpr const char* kEventPacketMd5 = "8a6101b351a64529ac77bd8b71074e52";
constexpr const char* kCameraInfo = "sensor_msgs/CameraInfo";
constexpr const char* kCameraInfoMd5 = "c9a58c1b0b154e0e6da7578cb991d214";

/// Reads ROS1-serialized fields; every read is checked against the message's size, and a short message
/// fails through the reader (naming the bag, the offset and the message index).
class Cursor {
 public:
  Cursor(const io_detail::RosbagReader& bag, const unsigned char* data, std::size_t size)
      : bag_(bag), data_(data), size_(size) {}
  void need(std::size_t n, const char* what) const {
    if (n > size_ - pos_) {
      bag_.failInMessage(fmt::format("malformed message: {} needs {} bytes at byte {} but the message has only {} "
                                     "bytes",
                                     what, n, pos_, size_));
    }
  }
  uint32_t u32(const char* what) {
    need(4, what);
    const unsigned char* p = data_ + pos_;
    pos_ += 4;
    return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
           (static_cast<uint32_t>(p[3]) << 24);
  }
  double f64(const char* what) {
    need(8, what);
    uint64_t bits = 0;
    for (int i = 7; i >= 0; --i) bits = (bits << 8) | data_[pos_ + static_cast<std::size_t>(i)];
    pos_ += 8;
    double value = 0;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  std::string string(const char* what) {
    const uint32_t n = u32(what);
    need(n, what);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  /// std_msgs/Header: returns the stamp in nanoseconds, and the frame_id when asked.
  int64_t header(std::string* frame_id = nullptr) {
    u32("the header's seq");
    const uint32_t sec = u32("the header's stamp");
    const uint32_t nsec = u32("the header's stamp");
    if (nsec >= 1'000'000'000u) {
      bag_.failInMessage(fmt::format("the header's stamp {} s + {} ns has a nanosecond part of 10^9 or more", sec,
                                     nsec));
    }
    std::string frame = string("the header's frame_id");
    if (frame_id) *frame_id = std::move(frame);
    return static_cast<int64_t>(sec) * 1'000'000'000 + nsec;
  }
  void skip(std::size_t n, const char* what) {
    need(n, what);
    pos_ += n;
  }
  /// The message must end here: a longer message is another definition than the one decoded.
  void end(const char* type) const {
    if (pos_ != size_) {
      bag_.failInMessage(fmt::format("malformed message: {} bytes are left after the last field of {} (a message of "
                                     "{} bytes)",
                                     size_ - pos_, type, size_));
    }
  }

 private:
  const io_detail::RosbagReader& bag_;
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// position (3 f64) then orientation (4 f64, x y z w) as a camera-to-world pose.
StampedPose readPose(Cursor& m, const io_detail::RosbagReader& bag, int64_t t_ns) {
  double v[7];
  for (double& x : v) x = m.f64("the pose");
  for (double x : v) {
    if (!std::isfinite(x)) bag.failInMessage("non-finite pose (NaN or inf)");
  }
  StampedPose pose;
  pose.t_ns = t_ns;
  pose.p_w_c = Eigen::Vector3d(v[0], v[1], v[2]);
  const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);  // w, x, y, z
  const double scale = q.coeffs().cwiseAbs().maxCoeff();
  if (!(scale > 0)) bag.failInMessage("zero quaternion (x y z w all 0)");
  pose.q_w_c = Eigen::Quaterniond(q.coeffs() / scale).normalized();
  return pose;
}

}  // namespace

bool isRosbag(const std::string& path) {
  FileHandle file = openFile(path, "rb");
  char head[9] = {};
  return file && std::fread(head, 1, sizeof(head), file.get()) == sizeof(head) &&
         std::memcmp(head, "#ROSBAG V", sizeof(head)) == 0;
}

std::string bagTopicSource(const std::string& path, const std::string& topic) {
  return fmt::format("{} (topic {})", path, topic);
}

namespace {

std::vector<std::string> topicsOfTypes(const std::string& path, std::initializer_list<const char*> types) {
  const io_detail::RosbagReader bag(path, io_detail::BagTopicQuery{});  // no type accepted: the index only
  std::vector<std::string> topics;
  for (const io_detail::BagTopic& t : bag.topics()) {
    for (const char* type : types) {
      if (t.type == type) topics.push_back(t.name);
    }
  }
  return topics;
}

}  // namespace

std::vector<std::string> rosbagPoseTopics(const std::string& path) {
  return topicsOfTypes(path, {kPoseStamped, kTransformStamped, kOdometry});
}

std::vector<std::string> rosbagCameraInfoTopics(const std::string& path) { return topicsOfTypes(path, {kCameraInfo}); }

namespace {

/// --gt-topic NAME or NAME:FRAME (ROS names have no ':'; graph resource names, wiki.ros.org/Names): FRAME
/// is the child frame of a TFMessage topic.
struct GtTopicChoice {
  std::string topic;
  std::string frame;
  bool tf = false;  ///< the topic is a TFMessage topic of the bag
};

GtTopicChoice parseGtTopic(const std::string& path, const std::string& requested) {
  GtTopicChoice choice;
  const std::size_t colon = requested.find(':');
  choice.topic = requested.substr(0, colon);
  if (colon != std::string::npos) choice.frame = requested.substr(colon + 1);
  if (!choice.topic.empty()) {
    for (const std::string& name : topicsOfTypes(path, {kTfMessage, kTfMessageOld})) choice.tf = choice.tf || name == choice.topic;
  }
  if (colon != std::string::npos && (!choice.tf || choice.frame.empty())) {
    throw InputError(path, fmt::format("{} '{}': TOPIC:FRAME names a child frame of a tf2_msgs/TFMessage topic, "
                                       "and {}",
                                       kGroundTruthTopicFlag, requested,
                                       choice.frame.empty() ? "the frame is empty"
                                                            : "the bag has no such topic '" + choice.topic + "'"));
  }
  return choice;
}

io_detail::BagTopicQuery poseQuery(const GtTopicChoice& choice) {
  io_detail::BagTopicQuery query;
  if (choice.tf) {
    query.types = {{kTfMessage, kTfMessageMd5}, {kTfMessageOld, kTfMessageMd5}};
  } else {
    query.types = {{kPoseStamped, kPoseStampedMd5}, {kTransformStamped, kTransformStampedMd5}, {kOdometry, kOdometryMd5}};
  }
  query.topic = choice.topic;
  query.flag = kGroundTruthTopicFlag;
  query.what = "pose";
  query.choose = "; choose one with --gt-topic NAME";
  return query;
}

/// The poses of one child frame of a TFMessage topic: every transform whose child_frame_id is `frame`, or,
/// without a frame, of the topic's only child frame. One parent frame per child.
void readTfPoses(io_detail::RosbagReader& bag, const std::string& path, const std::string& frame, BagGroundTruth& gt) {
  std::map<std::string, std::pair<std::string, StampedTrajectory>> children;  // child -> (parent, poses)
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  while (bag.nextRawMessage(data, size)) {
    Cursor m(bag, data, size);
    const uint32_t count = m.u32("the length of transforms");
    for (uint32_t i = 0; i < count; ++i) {
      std::string parent;
      const int64_t t_ns = m.header(&parent);
      const std::string child = m.string("child_frame_id");
      const StampedPose pose = readPose(m, bag, t_ns);
      if (!frame.empty() && child != frame) continue;
      auto [it, added] = children.try_emplace(child, parent, StampedTrajectory{});
      if (it->second.first != parent) {
        bag.failInMessage(fmt::format("frame {} has two parents, {} and {}: its poses are not one trajectory", child,
                                      it->second.first, parent));
      }
      StampedTrajectory& poses = it->second.second;
      if (!poses.empty() && pose.t_ns < poses.back().t_ns)
        bag.failInMessage(fmt::format("the stamps of frame {} go backwards; poses must be sorted by time", child));
      poses.push_back(pose);
    }
    m.end(bag.topicType().c_str());
  }
  if (children.size() != 1) {
    if (!frame.empty())
      throw InputError(path, fmt::format("the tf topic {} has no transform to frame {}", gt.topic, frame));
    std::string list;
    for (const auto& [child, entry] : children)
      list += fmt::format("{}{} (parent {}, {} poses)", list.empty() ? "" : ", ", child, entry.first, entry.second.size());
    throw InputError(path, children.empty()
                               ? fmt::format("the tf topic {} has no transforms", gt.topic)
                               : fmt::format("the tf topic {} has {} child frames: {}; choose one with --gt-topic "
                                             "{}:FRAME",
                                             gt.topic, children.size(), list, gt.topic));
  }
  gt.topic += ":" + children.begin()->first;
  gt.poses = std::move(children.begin()->second.second);
}

}  // namespace

void checkRosbagPoseTopic(const std::string& path, const std::string& topic) {
  const io_detail::RosbagReader bag(path, poseQuery(parseGtTopic(path, topic)));
}

std::optional<BagGroundTruth> readRosbagGroundTruth(const std::string& path, const std::string& topic) {
  const GtTopicChoice choice = parseGtTopic(path, topic);
  io_detail::RosbagReader bag(path, poseQuery(choice));
  if (!bag.hasTopic()) return std::nullopt;
  if (choice.tf) {
    BagGroundTruth gt;
    gt.topic = bag.topic();
    gt.type = bag.topicType();
    readTfPoses(bag, path, choice.frame, gt);
    return gt;
  }
  BagGroundTruth gt;
  gt.topic = bag.topic();
  gt.type = bag.topicType();
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  while (bag.nextRawMessage(data, size)) {
    Cursor m(bag, data, size);
    const int64_t t_ns = m.header();
    if (gt.type == kPoseStamped) {
      gt.poses.push_back(readPose(m, bag, t_ns));
    } else if (gt.type == kTransformStamped) {
      m.string("child_frame_id");
      gt.poses.push_back(readPose(m, bag, t_ns));
    } else {  // nav_msgs/Odometry: the pose; its covariance and the twist are not used
      m.string("child_frame_id");
      gt.poses.push_back(readPose(m, bag, t_ns));
      m.skip((36 + 6 + 36) * 8, "the pose covariance and the twist");
    }
    m.end(gt.type.c_str());
    if (gt.poses.size() > 1 && gt.poses.back().t_ns < gt.poses[gt.poses.size() - 2].t_ns)
      bag.failInMessage("the header stamp goes backwards; poses must be sorted by time");
  }
  if (gt.poses.empty())
    throw InputError(path, fmt::format("the pose topic {} ({}) has no messages", gt.topic, gt.type));
  return gt;
}

std::optional<int64_t> rosbagFirstPacketStamp(const std::string& path, const std::string& topic) {
  io_detail::BagTopicQuery query;
  query.types = {{kEventPacket, kEventPacketMd5}};
  for (const std::string& name : topicsOfTypes(path, {kEventPacket})) {
    if (name == topic) query.topic = topic;
  }
  if (query.topic.empty()) return std::nullopt;
  query.flag = "--topic";
  query.what = "event packet";
  io_detail::RosbagReader bag(path, query);
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  if (!bag.nextRawMessage(data, size)) return std::nullopt;
  Cursor m(bag, data, size);
  return m.header();
}

namespace {

/// A ROS name's namespace: what precedes its last '/' ("/dvs/events" -> "/dvs", "/events" -> "/"). Graph
/// resource names, wiki.ros.org/Names.
std::string rosNamespace(const std::string& name) {
  const std::size_t slash = name.rfind('/');
  return slash == std::string::npos || slash == 0 ? "/" : name.substr(0, slash);
}

}  // namespace

std::optional<BagCalibration> readRosbagCalibration(const std::string& path, const std::string& topic,
                                                    const std::string& event_topic) {
  io_detail::BagTopicQuery query;
  query.types = {{kCameraInfo, kCameraInfoMd5}};
  query.topic = topic;
  query.flag = kCameraInfoTopicFlag;
  query.what = "camera info";
  const std::string advice = fmt::format("; choose one with {} NAME, or give the camera's calibration as a file "
                                         "(--calib FILE, or calib.txt or a camchain beside the bag)",
                                         kCameraInfoTopicFlag);
  query.choose = advice;
  std::string note;
  // Several CameraInfo topics and none named: the one beside the event topic (a stereo or multi-camera bag).
  const std::vector<std::string> infos = topic.empty() ? rosbagCameraInfoTopics(path) : std::vector<std::string>{};
  if (infos.size() > 1) {
    std::string events = event_topic;
    if (events.empty()) {
      const std::vector<std::string> all = topicsOfTypes(path, {kEventArray, kEventPacket});
      if (all.size() == 1) events = all.front();
    }
    if (!events.empty()) {
      const std::string ns = rosNamespace(events);
      std::vector<std::string> near;
      for (const std::string& name : infos) {
        if (rosNamespace(name) == ns) near.push_back(name);
      }
      if (near.size() == 1) {
        query.topic = near.front();
        note = fmt::format("chosen among {} CameraInfo topics as the one in the namespace {} of the event topic {} ({} "
                           "NAME chooses another)",
                           infos.size(), ns, events, kCameraInfoTopicFlag);
      } else {
        query.choose = fmt::format("; {} in the namespace {} of the event topic {}{}",
                                   near.empty() ? std::string("none is") : fmt::format("{} are", near.size()), ns,
                                   events, advice);
      }
    }
  }
  io_detail::RosbagReader bag(path, query);
  if (!bag.hasTopic()) return std::nullopt;
  uint64_t messages = 0;
  for (const io_detail::BagTopic& t : bag.topics()) {
    if (t.name == bag.topic()) messages = t.messages;
  }
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  if (!bag.nextRawMessage(data, size)) {
    if (topic.empty()) return std::nullopt;
    throw InputError(path, fmt::format("the camera info topic {} ({}) has no messages", topic, kCameraInfoTopicFlag));
  }
  Cursor m(bag, data, size);
  m.header();
  const uint32_t height = m.u32("height");
  const uint32_t width = m.u32("width");
  CameraInfoFields info;
  info.height = height;
  info.width = width;
  info.distortion_model = m.string("distortion_model");
  const uint32_t count = m.u32("the length of D");
  m.need(std::size_t{count} * 8, "D");
  info.d.resize(count);
  for (double& x : info.d) x = m.f64("D");
  for (double& x : info.k) x = m.f64("K");
  m.skip((9 + 12) * 8, "R and P");
  m.skip(4 * 2 + 4 * 4 + 1, "binning and roi");
  m.end(kCameraInfo);
  try {
    return BagCalibration{cameraFromCameraInfo(info), bag.topic(), messages, note};
  } catch (const Error& e) {
    bag.failInMessage(e.what());
  }
}

}  // namespace asynevo
