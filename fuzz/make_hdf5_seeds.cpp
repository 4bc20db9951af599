// Writes the MVSEC-layout HDF5 seeds of fuzz/corpus/mvsec_events and fuzz/corpus/mvsec_groundtruth with
// the test suite's fixture writer (tests/io/mvsec_fixture.hpp). Not part of the build; run once:
//   g++ -std=c++17 -I tests fuzz/make_hdf5_seeds.cpp $(pkg-config --cflags --libs hdf5-serial) -o /tmp/seeds
//   /tmp/seeds fuzz/corpus
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "io/mvsec_fixture.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  std::vector<std::array<double, 4>> rows;
  for (int i = 0; i < 40; ++i) rows.push_back({double(i * 7 % 346), double(i * 5 % 260), 1.0 + 1e-4 * i, i % 2 ? 1.0 : -1.0});
  asynevo::testing::writeMvsecEvents(dir + "/mvsec_events/seed_40_events.hdf5", rows);
  asynevo::testing::writeMvsecEvents(dir + "/mvsec_events/seed_empty.hdf5", {});
  std::vector<std::array<double, 16>> poses;
  std::vector<double> times;
  for (int i = 0; i < 5; ++i) {
    poses.push_back({1, 0, 0, 0.1 * i, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    times.push_back(1.0 + 0.05 * i);
  }
  asynevo::testing::writeMvsecGroundTruth(dir + "/mvsec_groundtruth/seed_5_poses.hdf5", poses, times);
  asynevo::testing::writeMvsecGroundTruth(dir + "/mvsec_groundtruth/seed_empty.hdf5", {}, {});
  return 0;
}
