#pragma once
// The reader-throughput loop the event-format benchmarks share: open the file, read every packet, count
// the events; reported as items/s and "Mevents/s" (CPU time).

#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include "asynevo/io/event_reader.hpp"

namespace asynevo {

/// Reads `path` to its end once per iteration. With `warm_cache`, one untimed read first, so the figure
/// is that of a warm page cache. `options` for formats that need some (a DSEC file's sensor size).
inline void benchmarkReadAll(benchmark::State& state, const std::string& path, bool warm_cache,
                             const ReaderOptions& options = {}) {
  EventPacket packet;
  if (warm_cache) {
    auto reader = openEventReader(path, options);
    while (reader->read(packet)) {
    }
  }
  int64_t total = 0;
  for (auto _ : state) {
    auto reader = openEventReader(path, options);
    int64_t n = 0;
    while (reader->read(packet)) n += static_cast<int64_t>(packet.size());
    benchmark::DoNotOptimize(n);
    total += n;
  }
  state.SetItemsProcessed(total);
  state.counters["Mevents/s"] = benchmark::Counter(static_cast<double>(total) * 1e-6, benchmark::Counter::kIsRate);
}

}  // namespace asynevo
