// Fuzz harness: the ROS1 bag event reader (docs/reliability.md).
#include "event_reader_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return asynevo::fuzz::fuzzEventReader(data, size, "rosbag", ".bag");
}
