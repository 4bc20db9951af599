// Fuzz harness: the segments.txt reader of 'asynevo eval' (docs/reliability.md).
#include "asynevo/eval/segments.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".txt");
  rejectCleanly([&] {
    const auto segments = asynevo::eval::readSegments(input.path());
    require(!segments.empty(), "an accepted segments file has no segment");
    for (std::size_t i = 0; i < segments.size(); ++i) {
      require(segments[i].t0_ns <= segments[i].t1_ns, "an accepted segment ends before it starts");
      if (i > 0) require(segments[i].t0_ns > segments[i - 1].t1_ns, "accepted segments overlap");
    }
  });
  return 0;
}
