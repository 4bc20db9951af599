// DSEC-style HDF5 reader throughput (issue 22 target: >= 20 M events/s, warm page cache, one core).
// The inputs are generated once per process in the temp folder by the tests' layout fixture
// (tests/io/dsec_fixture.hpp): 10 M events at 10 M events/s on 640x480, DSEC's types (x, y uint16, p uint8,
// t uint32 µs, t_offset, ms_to_idx), chunks of 16384 values, uncompressed and Blosc+Zstd (DSEC's own
// compression; skipped without the plugin), and Blosc+Zstd in chunks of 2^20 values (4 MB of t, more than
// libhdf5's default 1 MB chunk cache); the uncompressed file again through a rectification map (DSEC's
// rectify_map.h5, a radial stretch that sends the corners outside the sensor). Run:
// build/bin/bench_io --benchmark_filter=Dsec
#include <benchmark/benchmark.h>
#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <utility>

#include "asynevo/io/event_reader.hpp"
#include "dsec_fixture.hpp"
#include "read_all_bench.hpp"

namespace asynevo {
namespace {

constexpr int64_t kEvents = 10'000'000;

std::string dsecFile(bool blosc, hsize_t chunk) {
  const std::string name =
      std::string("asynevo_bench_10M_dsec") + (blosc ? "_blosc" : "") + "_chunk" + std::to_string(chunk) + ".h5";
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  testing::DsecEvents events;
  events.x.resize(kEvents);
  events.y.resize(kEvents);
  events.t.resize(kEvents);
  events.p.resize(kEvents);
  std::minstd_rand rng(22);
  for (int64_t i = 0; i < kEvents; ++i) {
    events.x[i] = static_cast<uint16_t>(rng() % 640);
    events.y[i] = static_cast<uint16_t>(rng() % 480);
    events.t[i] = i / 10;
    events.p[i] = static_cast<uint8_t>(rng() & 1);
  }
  testing::DsecLayout layout;
  layout.t_offset_us = 49'599'300'523;
  layout.chunk = chunk;
  if (blosc) {
    layout.filter = 32001;
    layout.filter_values = {0, 0, 0, 0, 1, 2, 5};  // level 1, bit shuffle, Zstd
  }
  testing::writeDsecEvents(path, events, layout);
  return path;
}

ReaderOptions vga(const std::string& rectify_map = "none") {
  ReaderOptions options;
  options.width = 640;
  options.height = 480;
  options.rectify_map = rectify_map;  // "none": whatever lies in the temp folder, read raw pixels
  return options;
}

// A rectification map for 640x480: a radial stretch about the centre, 1 + 1e-6 r², so corners leave the sensor.
std::string rectifyMapFile() {
  const std::string path = (std::filesystem::temp_directory_path() / "asynevo_bench_rectify_map_vga.h5").string();
  testing::writeRectifyMap(path, testing::rectifyMapValues(640, 480, [](int x, int y) {
                             const float dx = static_cast<float>(x) - 319.5f, dy = static_cast<float>(y) - 239.5f;
                             const float s = 1.0f + 1e-6f * (dx * dx + dy * dy);
                             return std::pair<float, float>{319.5f + s * dx, 239.5f + s * dy};
                           }),
                           {480, 640, 2});
  return path;
}

void BM_DsecRead10M(benchmark::State& state) {
  static const std::string path = dsecFile(false, 16384);
  benchmarkReadAll(state, path, true, vga());
}

void BM_DsecRectifiedRead10M(benchmark::State& state) {
  static const std::string path = dsecFile(false, 16384);
  static const std::string map = rectifyMapFile();
  benchmarkReadAll(state, path, true, vga(map));
}

void BM_DsecBloscZstdRead10M(benchmark::State& state) {
  if (H5Zfilter_avail(32001) <= 0) {
    state.SkipWithError("the HDF5 Blosc filter plugin is not installed (Debian: hdf5-filter-plugin-blosc-serial)");
    return;
  }
  static const std::string path = dsecFile(true, 16384);
  benchmarkReadAll(state, path, true, vga());
}

void BM_DsecBloscZstdBigChunksRead10M(benchmark::State& state) {
  if (H5Zfilter_avail(32001) <= 0) {
    state.SkipWithError("the HDF5 Blosc filter plugin is not installed (Debian: hdf5-filter-plugin-blosc-serial)");
    return;
  }
  static const std::string path = dsecFile(true, hsize_t{1} << 20);
  benchmarkReadAll(state, path, true, vga());
}

BENCHMARK(BM_DsecRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DsecRectifiedRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DsecBloscZstdRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DsecBloscZstdBigChunksRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace asynevo
