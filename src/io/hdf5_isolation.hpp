#pragma once
// libhdf5 (1.10.8, Debian 12) parses a file's own structure (superblock, object headers, group heaps,
// B-trees, layout messages) without bounds checks: a corrupt file can crash it (SIGSEGV, SIGFPE) or make
// it allocate until the machine runs out of memory, inside calls such as H5Lexists and H5Dopen2, before
// any call returns an error a reader could check (fuzz/open/README.md lists the inputs found). So every
// HDF5 reader first parses its file in a forked child process: a crash or a runaway allocation ends the
// child only and becomes an InputError naming the file, and the reader then parses the file itself,
// knowing that libhdf5 survives it.

#include <cstdint>
#include <functional>
#include <string>

namespace asynevo::io_detail {

/// The 8 bytes an HDF5 file begins with (HDF5 File Format Specification, "Format Signature").
inline constexpr unsigned char kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// True when `path` can be read and begins with kHdf5Signature.
bool hasHdf5Signature(const std::string& path);

/// A valid file's structure and first packet take a few MiB and well under a second (the readers
/// stream: a chunk cache, one packet); the limits leave a wide margin.
struct Hdf5ChildLimits {
  uint64_t max_resident_bytes = uint64_t{1} << 30;  ///< the child is stopped beyond this growth
  double max_seconds = 30.0;                        ///< and after this long
  /// false: no child and no check, so the caller's own parse meets the file unguarded. Only for a fuzzing
  /// harness, whose fuzzer must see every fault, libhdf5's and the reader's alike (scripts/fuzz.sh sorts
  /// them afterwards).
  bool fork = true;
};

/// The limits parseHdf5InChild applies unless given others (a fuzzing harness shortens the time: under
/// a sanitizer, a runaway allocation grows slowly).
Hdf5ChildLimits& defaultHdf5ChildLimits();

/// Runs `parse` (which opens `path` with libhdf5 and reads what the caller is about to read) in a forked
/// child process and waits for it. Returns when the child finished, whether `parse` returned or threw
/// (the caller's own parse then meets the same error and reports it with its location). Throws
/// InputError naming `path` when the child died from a signal, exited otherwise, or went past `limits`.
/// Inside such a child it only runs `parse`, so readers that open other HDF5 files (DSEC events and
/// their rectification map) nest without forking again.
void parseHdf5InChild(const std::string& path, const std::function<void()>& parse,
                      const Hdf5ChildLimits& limits = defaultHdf5ChildLimits());

/// True in a child process of parseHdf5InChild.
bool insideHdf5Child();

}  // namespace asynevo::io_detail
