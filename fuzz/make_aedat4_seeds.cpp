// Writes the AEDAT 4.0 seeds of fuzz/corpus/aedat4_events with the test suite's specification-built
// fixture (tests/io/aedat4_fixture.hpp; the real samples in ../shared/data/formats/aedat4 include a GPL
// recording and stay out of the repository). Not part of the build; run once:
//   g++ -std=c++17 -I tests fuzz/make_aedat4_seeds.cpp -llz4 -lzstd -o /tmp/aedat4_seeds
//   /tmp/aedat4_seeds fuzz/corpus
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "io/aedat4_fixture.hpp"

namespace fx = asynevo::testing::aedat4;

namespace {

std::string file(int32_t compression, const std::vector<std::pair<int, std::string>>& packets, bool table) {
  const std::string xml = fx::infoXml({{1, "EVTS", "events", 64, 32}, {2, "IMUS", "imu"}, {5, "FRME", "frames"}});
  std::string body;
  for (const auto& [stream, payload] : packets) body += fx::packet(stream, fx::compress(payload, compression));
  const auto position = static_cast<int64_t>(fx::kMagic.size() + fx::ioHeader(compression, -1, xml).size() + body.size());
  return fx::kMagic + fx::ioHeader(compression, table ? position : -1, xml) + body + (table ? "TABLE" : "");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/aedat4_events/";
  const std::vector<std::pair<int, std::string>> packets = {
      {1, fx::eventPacket({{1000, 1, 2, 1}, {1000, 3, 4, 0}, {1500, 63, 31, 1}})},
      {2, fx::imuPacket(2, 1200)},
      {5, "frame"},
      {1, fx::eventPacket({{2000, 10, 11, 0}, {2500, 12, 13, 1}})}};
  const std::pair<const char*, std::string> seeds[] = {
      {"seed_none.aedat4", file(fx::kNone, packets, true)},
      {"seed_lz4.aedat4", file(fx::kLz4, packets, false)},
      {"seed_zstd.aedat4", file(fx::kZstd, packets, true)},
      {"seed_header_only.aedat4", file(fx::kLz4, {}, false)},
  };
  for (const auto& [name, bytes] : seeds) std::ofstream(dir + name, std::ios::binary) << bytes;
  const std::string cut = file(fx::kLz4, packets, false);
  std::ofstream(dir + "seed_truncated.aedat4", std::ios::binary) << cut.substr(0, cut.size() - 7);
  return 0;
}
