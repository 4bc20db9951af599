// Fuzz harness: the DSEC-style HDF5 event reader (docs/reliability.md), with DSEC's 640x480 sensor size
// (the files state none).
#include "event_reader_harness.hpp"
#include "hdf5_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  asynevo::fuzz::configureHdf5Isolation();
  return asynevo::fuzz::fuzzEventReader(data, size, "dsec", ".h5", 640, 480);
}
