// AEDAT 4.0 reader throughput (issue 22 target: >= 20 M events/s per reader, warm page cache, one core).
// The inputs are generated once per process in the temp folder: 10 M events at 10 M events/s over a
// 1280x720 sensor, in EventPacket FlatBuffers of 8192 events, written byte by byte from the published
// specification by the test fixture (tests/io/aedat4_fixture.hpp), uncompressed, LZ4 (DV's default) and
// Zstd. Run: build/bin/bench_io --benchmark_filter=Aedat4
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "aedat4_fixture.hpp"
#include "asynevo/io/event_reader.hpp"
#include "read_all_bench.hpp"

namespace asynevo {
namespace {

namespace fx = testing::aedat4;

constexpr int64_t kEvents = 10'000'000;
constexpr int64_t kPacketEvents = 8192;

std::string aedat4File(int32_t compression, const char* name) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream out(path, std::ios::binary);
  out << fx::kMagic << fx::ioHeader(compression, -1, fx::infoXml({{0, "EVTS", "events", 1280, 720}}));
  std::minstd_rand rng(21);
  std::vector<fx::RawEvent> events;
  for (int64_t i = 0; i < kEvents; i += kPacketEvents) {
    events.clear();
    for (int64_t j = i; j < i + kPacketEvents && j < kEvents; ++j) {
      events.push_back({1'000'000 + j / 10, static_cast<int>(rng() % 1280), static_cast<int>(rng() % 720),
                        static_cast<int>(rng() & 1)});
    }
    out << fx::packet(0, fx::compress(fx::eventPacket(events), compression));
  }
  return path;
}

const std::string& noneFile() {
  static const std::string path = aedat4File(fx::kNone, "asynevo_bench_10M_events_none.aedat4");
  return path;
}
const std::string& lz4File() {
  static const std::string path = aedat4File(fx::kLz4, "asynevo_bench_10M_events_lz4.aedat4");
  return path;
}
const std::string& zstdFile() {
  static const std::string path = aedat4File(fx::kZstd, "asynevo_bench_10M_events_zstd.aedat4");
  return path;
}

void BM_Aedat4UncompressedRead10M(benchmark::State& state) { benchmarkReadAll(state, noneFile(), true); }
void BM_Aedat4Lz4Read10M(benchmark::State& state) { benchmarkReadAll(state, lz4File(), true); }
void BM_Aedat4ZstdRead10M(benchmark::State& state) { benchmarkReadAll(state, zstdFile(), true); }

BENCHMARK(BM_Aedat4UncompressedRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Aedat4Lz4Read10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Aedat4ZstdRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace asynevo
