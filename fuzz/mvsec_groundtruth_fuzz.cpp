// Fuzz harness: the MVSEC ground-truth HDF5 reader (docs/reliability.md).
#include "asynevo/io/groundtruth_reader.hpp"
#include "fuzz_input.hpp"
#include "hdf5_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  asynevo::fuzz::configureHdf5Isolation();
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".hdf5");
  rejectCleanly([&] { requireValidTrajectory(asynevo::readMvsecGroundTruth(input.path())); });
  return 0;
}
