// Prophesee reader throughput (issue 22 target: >= 20 M events/s per reader, warm page cache, one core).
// The inputs are generated once per process in the temp folder, about 10 M events each, written byte by
// byte from the published layouts (EVT 3.0, EVT 2.0, DAT): an event stream at 10 M events/s over a
// 1280x720 sensor, with the EVT 3.0 mix of single events (ADDR_Y + ADDR_X) and 12-wide vectors similar to
// a real Gen4 recording. Run: build/bin/bench_io --benchmark_filter=Prophesee
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "read_all_bench.hpp"

namespace asynevo {
namespace {

constexpr int64_t kTargetEvents = 10'000'000;

class ByteFile {
 public:
  explicit ByteFile(const std::string& path) : file_(std::fopen(path.c_str(), "wb")) {}
  ~ByteFile() {
    flush();
    std::fclose(file_);
  }
  ByteFile(const ByteFile&) = delete;
  ByteFile& operator=(const ByteFile&) = delete;
  void text(const std::string& s) { bytes_.insert(bytes_.end(), s.begin(), s.end()); }
  void u8(uint32_t v) { bytes_.push_back(static_cast<unsigned char>(v)); }
  void u16(uint32_t v) {
    u8(v & 0xFF);
    u8((v >> 8) & 0xFF);
  }
  void u32(uint32_t v) {
    u16(v & 0xFFFF);
    u16(v >> 16);
  }
  void flushIfLarge() {
    if (bytes_.size() > (1u << 20)) flush();
  }

 private:
  void flush() {
    std::fwrite(bytes_.data(), 1, bytes_.size(), file_);
    bytes_.clear();
  }
  std::FILE* file_;
  std::vector<unsigned char> bytes_;
};

std::string benchPath(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

const std::string& evt3File() {
  static const std::string path = [] {
    const std::string p = benchPath("asynevo_bench_10M_events_evt3.raw");
    std::minstd_rand rng(11);
    ByteFile f(p);
    f.text("% evt 3.0\n% format EVT3;height=720;width=1280\n% geometry 1280x720\n% end\n");
    int64_t events = 0;
    uint32_t last_high = UINT32_MAX;
    uint32_t last_low = UINT32_MAX;
    for (int64_t step = 0; events < kTargetEvents; ++step) {
      const uint64_t t_us = 1'000'000 + static_cast<uint64_t>(step / 10);  // 10 groups per µs
      const uint32_t high = static_cast<uint32_t>(t_us >> 12) & 0xFFF;
      const uint32_t low = static_cast<uint32_t>(t_us) & 0xFFF;
      if (high != last_high) f.u16(0x8000 | high);
      if (low != last_low) f.u16(0x6000 | low);
      last_high = high;
      last_low = low;
      f.u16(static_cast<uint32_t>(rng() % 720));  // ADDR_Y
      if (step % 8 == 0) {                          // a 12-wide vector with a few events
        const uint32_t mask = static_cast<uint32_t>(rng() & 0xFFF) | 1u;
        f.u16(0x3000 | ((rng() & 1) << 11) | static_cast<uint32_t>(rng() % 1260));
        f.u16(0x4000 | mask);
        events += __builtin_popcount(mask);
      } else {
        f.u16(0x2000 | ((rng() & 1) << 11) | static_cast<uint32_t>(rng() % 1280));
        ++events;
      }
      f.flushIfLarge();
    }
    return p;
  }();
  return path;
}

const std::string& evt2File() {
  static const std::string path = [] {
    const std::string p = benchPath("asynevo_bench_10M_events_evt2.raw");
    std::minstd_rand rng(12);
    ByteFile f(p);
    f.text("% evt 2.0\n% format EVT2;height=720;width=1280\n% end\n");
    uint64_t last_high = UINT64_MAX;
    for (int64_t i = 0; i < kTargetEvents; ++i) {
      const uint64_t t_us = 1'000'000 + static_cast<uint64_t>(i / 10);
      if ((t_us >> 6) != last_high) f.u32(0x80000000u | static_cast<uint32_t>(t_us >> 6));
      last_high = t_us >> 6;
      f.u32(((rng() & 1) << 28) | (static_cast<uint32_t>(t_us & 0x3F) << 22) |
            (static_cast<uint32_t>(rng() % 1280) << 11) | static_cast<uint32_t>(rng() % 720));
      f.flushIfLarge();
    }
    return p;
  }();
  return path;
}

const std::string& datFile() {
  static const std::string path = [] {
    const std::string p = benchPath("asynevo_bench_10M_events.dat");
    std::minstd_rand rng(13);
    ByteFile f(p);
    f.text("% Data file containing CD events\n% Version 2\n% Width 1280\n% Height 720\n");
    f.u8(0x0C);
    f.u8(8);
    for (int64_t i = 0; i < kTargetEvents; ++i) {
      f.u32(static_cast<uint32_t>(1'000'000 + i / 10));
      f.u32(static_cast<uint32_t>(rng() % 1280) | (static_cast<uint32_t>(rng() % 720) << 14) |
            static_cast<uint32_t>((rng() & 1) << 28));
      f.flushIfLarge();
    }
    return p;
  }();
  return path;
}

void BM_PropheseeEvt3Read10M(benchmark::State& state) { benchmarkReadAll(state, evt3File(), true); }
void BM_PropheseeEvt2Read10M(benchmark::State& state) { benchmarkReadAll(state, evt2File(), true); }
void BM_PropheseeDatRead10M(benchmark::State& state) { benchmarkReadAll(state, datFile(), true); }

BENCHMARK(BM_PropheseeEvt3Read10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_PropheseeEvt2Read10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_PropheseeDatRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace asynevo
