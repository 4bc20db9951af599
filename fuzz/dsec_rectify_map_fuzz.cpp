// Fuzz harness: DSEC's rectification map (rectify_map.h5, src/io/dsec_rectify.hpp) for a small 8x6 sensor:
// a map is read whole or rejected with an InputError, and every pixel it keeps lands inside the sensor.
#include "fuzz_input.hpp"
#include "hdf5_harness.hpp"
#include "io/dsec_rectify.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  asynevo::fuzz::configureHdf5Isolation();
  constexpr int kWidth = 8, kHeight = 6;
  const asynevo::fuzz::InputFile input(data, size, ".h5");
  asynevo::fuzz::rejectCleanly([&] {
    const asynevo::io_detail::RectifyMap map(input.path(), kWidth, kHeight, "fuzz");
    uint64_t outside = 0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        uint16_t xr = 0, yr = 0;
        if (!map.map(x, y, xr, yr)) {
          ++outside;
          continue;
        }
        asynevo::fuzz::require(xr < kWidth && yr < kHeight, "a rectified pixel outside the sensor");
      }
    }
    asynevo::fuzz::require(outside == map.pixelsOutside(), "pixelsOutside() differs from the pixels mapped outside");
  });
  return 0;
}
