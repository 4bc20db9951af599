// Fuzz harness: the Kalibr camchain YAML parser (docs/reliability.md).
#include "asynevo/io/calibration_io.hpp"
#include "calibration_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const asynevo::fuzz::InputFile input(data, size, ".yaml");
  asynevo::fuzz::rejectCleanly(
      [&] { asynevo::fuzz::requireValidCamera(asynevo::readKalibrCalibration(input.path())); });
  return 0;
}
