// Fuzz harness: the TUM trajectory reader and the ECD groundtruth.txt reader (docs/reliability.md).
#include "asynevo/io/trajectory_io.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".txt");
  rejectCleanly([&] { requireValidTrajectory(asynevo::readTumTrajectory(input.path())); });
  rejectCleanly([&] { requireValidTrajectory(asynevo::readEcdGroundTruth(input.path())); });
  return 0;
}
