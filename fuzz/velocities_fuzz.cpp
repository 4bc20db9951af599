// Fuzz harness: the velocities.txt reader (docs/reliability.md).
#include "asynevo/io/trajectory_io.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".txt");
  rejectCleanly([&] {
    const auto twists = asynevo::readVelocities(input.path());
    for (std::size_t i = 0; i < twists.size(); ++i) {
      require(twists[i].v_c.allFinite() && twists[i].w_c.allFinite(), "an accepted twist is not finite");
      if (i > 0) require(twists[i].t_ns >= twists[i - 1].t_ns, "accepted twists go back in time");
    }
  });
  return 0;
}
