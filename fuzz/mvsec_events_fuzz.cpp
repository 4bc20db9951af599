// Fuzz harness: the mvsec event reader (docs/reliability.md).
#include "event_reader_harness.hpp"
#include "hdf5_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  asynevo::fuzz::configureHdf5Isolation();
  return asynevo::fuzz::fuzzEventReader(data, size, "mvsec", ".hdf5");
}
