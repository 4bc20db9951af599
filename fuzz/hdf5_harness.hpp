#pragma once
// The HDF5 harnesses: libhdf5 parses each input in a child process first (src/io/hdf5_isolation.hpp).
// Under the sanitizers a runaway allocation inside libhdf5 grows slowly (every malloc unwinds its
// stack), so the child gets 1 s instead of the default 30 before it is stopped as a corrupt file (a valid
// input takes tens of milliseconds there).

#include "io/hdf5_isolation.hpp"

namespace asynevo::fuzz {

inline void shortenHdf5ChildTime() {
  static const bool once = [] {
    io_detail::defaultHdf5ChildLimits().max_seconds = 1.0;
    return true;
  }();
  (void)once;
}

}  // namespace asynevo::fuzz
