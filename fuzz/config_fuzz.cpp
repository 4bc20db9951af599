// Fuzz harness: the configuration loader (docs/reliability.md). A configuration it accepts is valid.
#include "asynevo/core/config/config.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace asynevo::fuzz;
  const InputFile input(data, size, ".yaml");
  asynevo::Config config;
  bool accepted = false;
  rejectCleanly([&] {
    config = asynevo::loadConfig(input.path());
    accepted = true;
  });
  if (accepted) {
    try {
      config.validate();
    } catch (const std::exception& e) {
      finding(std::string("loadConfig accepted a configuration that validate() rejects: ") + e.what());
    }
  }
  return 0;
}
