// HDF5 parsing in a child process first (src/io/hdf5_isolation.hpp): what the child's end becomes in the
// parent, and the corrupt files libhdf5 1.10.8 crashes on, which readers now reject with an InputError.
#include "../../src/io/hdf5_isolation.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/groundtruth_reader.hpp"

namespace asynevo::io_detail {
namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Hdf5Isolation, AChildThatFinishesOrThrowsLeavesTheParseToTheCaller) {
  EXPECT_NO_THROW(parseHdf5InChild("file.h5", [] {}));
  // An error the parse reports is the caller's to report again, with its location: no error here.
  EXPECT_NO_THROW(parseHdf5InChild("file.h5", [] { throw std::runtime_error("dataset missing"); }));
  EXPECT_FALSE(insideHdf5Child());
}

TEST(Hdf5Isolation, AChildThatCrashesIsAnInputErrorNamingTheFileAndTheSignal) {
  const std::string segv = errorOf([] { parseHdf5InChild("corrupt.h5", [] { raise(SIGSEGV); }); });
  EXPECT_NE(segv.find("corrupt.h5"), std::string::npos) << segv;
  EXPECT_NE(segv.find("libhdf5 crashed (signal 11"), std::string::npos) << segv;
  const std::string fpe = errorOf([] { parseHdf5InChild("corrupt.h5", [] { raise(SIGFPE); }); });
  EXPECT_NE(fpe.find("signal 8"), std::string::npos) << fpe;
  const std::string exit_code = errorOf([] { parseHdf5InChild("corrupt.h5", [] { _exit(1); }); });
  EXPECT_NE(exit_code.find("exit code 1"), std::string::npos) << exit_code;
}

TEST(Hdf5Isolation, AChildPastItsMemoryOrTimeLimitIsStopped) {
  Hdf5ChildLimits limits;
  limits.max_resident_bytes = uint64_t{32} << 20;
  const std::string memory = errorOf([&] {
    parseHdf5InChild(
        "big.h5",
        [] {
          std::vector<std::vector<char>> blocks;
          for (int i = 0; i < 64; ++i) {  // 256 MiB, touched, a little at a time
            blocks.emplace_back(std::size_t{4} << 20);
            std::memset(blocks.back().data(), 1, blocks.back().size());
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
          }
        },
        limits);
  });
  EXPECT_NE(memory.find("big.h5"), std::string::npos) << memory;
  EXPECT_NE(memory.find("more than 32 MiB"), std::string::npos) << memory;

  limits = Hdf5ChildLimits{};
  limits.max_seconds = 0.2;
  const auto start = std::chrono::steady_clock::now();
  const std::string slow = errorOf([&] {
    parseHdf5InChild(
        "slow.h5", [] { std::this_thread::sleep_for(std::chrono::seconds(30)); }, limits);
  });
  EXPECT_NE(slow.find("more than 0.2 s"), std::string::npos) << slow;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
}

TEST(Hdf5Isolation, UnguardedThereIsNoCheckAndTheCallerParsesAlone) {
  // A fuzzing harness's setting (fuzz/hdf5_harness.hpp): a parse that would crash is not even run.
  Hdf5ChildLimits limits;
  limits.fork = false;
  int runs = 0;
  EXPECT_NO_THROW(parseHdf5InChild("file.h5", [&] { ++runs; raise(SIGSEGV); }, limits));
  EXPECT_EQ(runs, 0);
  EXPECT_FALSE(insideHdf5Child());
  // Guarded, the same parse is a located error.
  EXPECT_NE(errorOf([] { parseHdf5InChild("file.h5", [] { raise(SIGSEGV); }); }).find("file.h5"),
            std::string::npos);
}

TEST(Hdf5Isolation, InsideAChildNestedChecksRunInPlace) {
  // A DSEC reader opens its rectification map while the child checks the events file: no second fork.
  EXPECT_NO_THROW(parseHdf5InChild("outer.h5", [] {
    if (!insideHdf5Child()) _exit(3);
    parseHdf5InChild("inner.h5", [] {
      if (!insideHdf5Child()) _exit(4);
    });
  }));
}

// The inputs the fuzzers found that crash libhdf5 1.10.8 itself (fuzz/corpus/*/hdf5_*), through the
// public readers: a located InputError, no crash.
const std::string kCorpus = ASYNEVO_FUZZ_CORPUS_DIR;

TEST(Hdf5Isolation, CorruptFilesThatCrashLibhdf5AreInputErrors) {
  ReaderOptions options;
  options.width = 640;
  options.height = 480;
  options.rectify_map = "none";
  const std::string fpe_file = kCorpus + "/dsec_events/hdf5_chunk_dim_zero_fpe.h5";
  const std::string fpe = errorOf([&] { openEventReader(fpe_file, options); });
  EXPECT_NE(fpe.find(fpe_file), std::string::npos) << fpe;
  EXPECT_NE(fpe.find("libhdf5 crashed (signal 8"), std::string::npos) << fpe;

  const std::string heap_file = kCorpus + "/mvsec_groundtruth/hdf5_local_heap_null_memcpy.hdf5";
  const std::string heap = errorOf([&] { readGroundTruth(heap_file); });
  EXPECT_NE(heap.find(heap_file), std::string::npos) << heap;
  EXPECT_NE(heap.find("libhdf5 crashed (signal 11"), std::string::npos) << heap;
}

}  // namespace
}  // namespace asynevo::io_detail
