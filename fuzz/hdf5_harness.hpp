#pragma once
// The HDF5 harnesses. By default libhdf5 parses each input in a child process first, as in every run
// (src/io/hdf5_isolation.hpp). Under the sanitizers a runaway allocation inside libhdf5 grows slowly
// (every malloc unwinds its stack), so the child gets 1 s instead of the default 30 before it is stopped
// as a corrupt file (a valid input takes tens of milliseconds there).
//
// With ASYNEVO_FUZZ_HDF5_UNGUARDED=1 in the environment, the input is parsed in the fuzzer's own process
// instead: a fork per input costs most of an execution (the fuzzer's process is large), and a fault in
// the child would be reported as a corrupt file, hiding the reader's own faults from the fuzzer.
// scripts/fuzz.sh runs the long runs that way, lets libFuzzer go on past crashes, and then sorts what
// crashed into libhdf5's faults (which the child contains) and the reader's (findings).
//
// The Blosc filter plugin (DSEC files) leaks its global context. libhdf5 unloads the plugin before the
// leak check, which leaves the leak's frames unknown to a fast unwinder. So the harness loads the plugin
// once itself, never to be unloaded, and fuzz/lsan.supp names its library.

#include <dlfcn.h>
#include <hdf5.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "io/hdf5_isolation.hpp"

namespace asynevo::fuzz {

/// Loads the Blosc plugin from libhdf5's first plugin folder with RTLD_NODELETE (nothing when absent).
inline void pinBloscPlugin() {
  char folder[4096] = {};
  if (H5PLget(0, folder, sizeof folder) <= 0) return;
  const std::string plugin = std::string(folder) + "/libH5Zblosc.so";
  (void)dlopen(plugin.c_str(), RTLD_NOW | RTLD_NODELETE);
}

inline void configureHdf5Isolation() {
  static const bool once = [] {
    io_detail::Hdf5ChildLimits& limits = io_detail::defaultHdf5ChildLimits();
    limits.max_seconds = 1.0;
    pinBloscPlugin();
    const char* unguarded = std::getenv("ASYNEVO_FUZZ_HDF5_UNGUARDED");
    limits.fork = unguarded == nullptr || std::strcmp(unguarded, "1") != 0;
    return true;
  }();
  (void)once;
}

}  // namespace asynevo::fuzz
