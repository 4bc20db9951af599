// Event reader throughput: ECD text parsing and .aevt reading on a generated 10 M-event file, from a
// warm page cache, one core. Run: build/bin/bench_io [--benchmark_filter=...]
// Target (issue 2): ECD text ≥ 10 M events/s.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "asynevo/core/time.hpp"
#include "asynevo/io/event_file.hpp"
#include "asynevo/io/event_reader.hpp"
#include "read_all_bench.hpp"

namespace asynevo {
namespace {

constexpr int64_t kEvents = 10'000'000;

// Writes (once per process) a realistic ECD text file: 1 M events/s, DAVIS240C pixels, 9 decimals as
// in the ECD files. Returns its path.
const std::string& ecdFile() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "asynevo_bench_10M_events.txt").string();
    if (std::filesystem::exists(p) && std::filesystem::file_size(p) > 200'000'000) return p;
    std::minstd_rand rng(7);
    FILE* f = std::fopen(p.c_str(), "w");
    char t[32];
    for (int64_t i = 0; i < kEvents; ++i) {
      formatNsAsSeconds(1'000'000'000 + i * 1000 + static_cast<int64_t>(rng() % 1000), t);
      std::fprintf(f, "%s %u %u %u\n", t, static_cast<unsigned>(rng() % 240), static_cast<unsigned>(rng() % 180), static_cast<unsigned>(rng() % 2));
    }
    std::fclose(f);
    return p;
  }();
  return path;
}

const std::string& aevtFile() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() / "asynevo_bench_10M_events.aevt").string();
    auto reader = openEventReader(ecdFile());
    EventFileWriter writer(p, 240, 180);
    EventPacket packet;
    while (reader->read(packet)) writer.write(packet);
    writer.close();
    return p;
  }();
  return path;
}

void BM_EcdTextRead10M(benchmark::State& state) { benchmarkReadAll(state, ecdFile(), false); }
void BM_AevtRead10M(benchmark::State& state) { benchmarkReadAll(state, aevtFile(), false); }

void BM_ParseSecondsToNs(benchmark::State& state) {
  const std::string_view text = "13.582596001";
  for (auto _ : state) benchmark::DoNotOptimize(parseSecondsToNs(text));
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_ParseSecondsToNs);
BENCHMARK(BM_EcdTextRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_AevtRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace asynevo

BENCHMARK_MAIN();
