// Fuzz harness: the iniVation AEDAT 4.0 event reader (docs/reliability.md).
#include "event_reader_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return asynevo::fuzz::fuzzEventReader(data, size, "aedat4", ".aedat4");
}
