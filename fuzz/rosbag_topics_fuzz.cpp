// Fuzz harness: the ROS1 bag ground-truth (pose topics, one frame of a tf topic) and calibration (CameraInfo) readers
// (docs/reliability.md, docs/reference/formats_rosbag.md).
#include "asynevo/io/rosbag_topics.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".bag");
  rejectCleanly([&] {
    const auto gt = asynevo::readRosbagGroundTruth(input.path());
    if (gt) {
      require(!gt->poses.empty(), "an accepted pose topic holds no pose");
      requireValidTrajectory(gt->poses);
    }
  });
  // A tf topic is read only when named: its child frame "cam" (the seed's), then the topic alone.
  for (const char* topic : {"/tf:cam", "/tf"}) {
    rejectCleanly([&] {
      const auto gt = asynevo::readRosbagGroundTruth(input.path(), topic);
      if (gt) {
        require(!gt->poses.empty(), "an accepted tf frame holds no pose");
        requireValidTrajectory(gt->poses);
      }
    });
  }
  rejectCleanly([&] {
    const auto calib = asynevo::readRosbagCalibration(input.path());
    if (calib) require(calib->camera.width() > 0 && calib->camera.height() > 0, "an accepted camera has no size");
  });
  return 0;
}
