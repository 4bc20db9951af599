// ROS1 bag reader throughput (issue 22 target: >= 20 M events/s per reader, warm page cache, one core).
// The inputs are generated once per process in the temp folder by the tests' specification-built bag
// fixture (tests/io/rosbag_fixture.hpp): 10 M events at 10 M events/s over a 640x480 sensor, in
// messages of 4096 events, chunks of about 768 KiB (ROS's default chunk threshold):
//   - dvs_msgs/EventArray, uncompressed, lz4 and (2 M events; bz2 is slow to write) bz2 chunks;
//   - event_camera_msgs/EventPacket with EVT 3.0 payloads (a TIME_HIGH/TIME_LOW pair per 16 µs
//     step, then ADDR_Y + ADDR_X per event), uncompressed.
// Run: build/bin/bench_io --benchmark_filter=Rosbag
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "asynevo/io/event_reader.hpp"
#include "chunk_compression.hpp"
#include "read_all_bench.hpp"
#include "rosbag_fixture.hpp"

namespace asynevo {
namespace {

namespace bag = testing::bag;

constexpr int kMessageEvents = 4096;
constexpr std::size_t kChunkBytes = 768 * 1024;
constexpr uint64_t kT0 = 1'600'000'000'000'000'000ull;

/// Groups messages into chunks of about kChunkBytes and writes the bag.
std::string writeBag(const char* name, const bag::Connection& connection, const std::vector<bag::Message>& messages,
                     const std::string& compression, std::string (*compress)(const std::string&)) {
  std::vector<bag::Chunk> chunks(1);
  std::size_t bytes = 0;
  for (const bag::Message& m : messages) {
    if (bytes > kChunkBytes) {
      chunks.emplace_back();
      bytes = 0;
    }
    chunks.back().messages.push_back(m);
    bytes += m.data.size();
  }
  for (bag::Chunk& c : chunks) {
    c.compression = compression;
    if (compress != nullptr) c.compress = compress;
  }
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path, std::ios::binary) << bag::buildBag({connection}, chunks);
  return path;
}

std::string eventArrayBag(const char* name, int64_t events, const std::string& compression,
                          std::string (*compress)(const std::string&)) {
  const bag::Connection dvs{0, "/dvs/events", bag::kEventArrayType, bag::kEventArrayMd5, bag::kEventArrayDefinition};
  std::minstd_rand rng(22);
  std::vector<bag::Message> messages;
  std::vector<bag::DvsEvent> batch;
  for (int64_t i = 0; i < events; i += kMessageEvents) {
    batch.clear();
    for (int64_t j = i; j < i + kMessageEvents && j < events; ++j) {
      batch.push_back({static_cast<uint16_t>(rng() % 640), static_cast<uint16_t>(rng() % 480),
                       kT0 + static_cast<uint64_t>(j) * 100, (rng() & 1) != 0});
    }
    messages.push_back({0, batch.front().t_ns, bag::eventArray(640, 480, batch)});
  }
  return writeBag(name, dvs, messages, compression, compress);
}

std::string evt3Bag(const char* name, int64_t events) {
  const bag::Connection packets{0, "/event_camera/events", bag::kEventPacketType, bag::kEventPacketMd5, "-"};
  std::minstd_rand rng(23);
  std::vector<bag::Message> messages;
  std::string payload;
  uint64_t last_us = UINT64_MAX;
  for (int64_t i = 0; i < events; ++i) {
    const uint64_t t_us = static_cast<uint64_t>(i) / 10;  // 10 events per µs
    if (t_us / 16 != last_us / 16 || last_us == UINT64_MAX) {
      payload += bag::u16(0x8000 | ((t_us >> 12) & 0xFFF)) + bag::u16(0x6000 | (t_us & 0xFFF));
    } else if (t_us != last_us) {
      payload += bag::u16(0x6000 | (t_us & 0xFFF));
    }
    last_us = t_us;
    payload += bag::u16(static_cast<uint32_t>(rng() % 480)) +
               bag::u16(0x2000 | ((rng() & 1) << 11) | static_cast<uint32_t>(rng() % 640));
    if ((i + 1) % kMessageEvents == 0 || i + 1 == events) {
      messages.push_back({0, kT0 + t_us * 1000, bag::eventPacket(640, 480, "evt3", payload, messages.size())});
      payload.clear();
    }
  }
  return writeBag(name, packets, messages, "none", nullptr);
}

void BM_RosbagEventArrayRead10M(benchmark::State& state) {
  static const std::string path = eventArrayBag("asynevo_bench_10M_events_none.bag", 10'000'000, "none", nullptr);
  benchmarkReadAll(state, path, true);
}
void BM_RosbagEventArrayLz4Read10M(benchmark::State& state) {
  static const std::string path = eventArrayBag("asynevo_bench_10M_events_lz4.bag", 10'000'000, "lz4", bag::lz4);
  benchmarkReadAll(state, path, true);
}
void BM_RosbagEventArrayBz2Read2M(benchmark::State& state) {
  static const std::string path = eventArrayBag("asynevo_bench_2M_events_bz2.bag", 2'000'000, "bz2", bag::bz2);
  benchmarkReadAll(state, path, true);
}
void BM_RosbagEventPacketEvt3Read10M(benchmark::State& state) {
  static const std::string path = evt3Bag("asynevo_bench_10M_events_evt3.bag", 10'000'000);
  benchmarkReadAll(state, path, true);
}

BENCHMARK(BM_RosbagEventArrayRead10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RosbagEventArrayLz4Read10M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RosbagEventArrayBz2Read2M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RosbagEventPacketEvt3Read10M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace asynevo
