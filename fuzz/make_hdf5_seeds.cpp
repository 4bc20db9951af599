// Writes the MVSEC-layout HDF5 seeds of fuzz/corpus/mvsec_events and fuzz/corpus/mvsec_groundtruth, and the
// DSEC-style seeds of fuzz/corpus/dsec_events and the rectification maps of fuzz/corpus/dsec_rectify_map, with the test suite's fixture writers
// (tests/io/mvsec_fixture.hpp, tests/io/dsec_fixture.hpp). Not part of the build; run once (the Blosc seed
// needs hdf5-filter-plugin-blosc-serial):
//   g++ -std=c++17 -I tests fuzz/make_hdf5_seeds.cpp $(pkg-config --cflags --libs hdf5-serial) -o /tmp/seeds
//   /tmp/seeds fuzz/corpus
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "io/dsec_fixture.hpp"
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

  namespace t = asynevo::testing;
  const t::DsecEvents events = t::syntheticDsecEvents(40);
  t::DsecLayout dsec;
  dsec.t_offset_us = 49'599'300'523;
  dsec.chunk = 16;
  t::writeDsecEvents(dir + "/dsec_events/seed_40_events.h5", events, dsec);
  t::writeDsecEvents(dir + "/dsec_events/seed_empty.h5", {}, dsec);
  t::DsecLayout tum;  // TUM-VIE: int64 t, no t_offset
  tum.t_type = H5T_STD_I64LE;
  tum.write_t_offset = false;
  tum.chunk = 16;
  t::writeDsecEvents(dir + "/dsec_events/seed_tumvie_40_events.h5", events, tum);
  t::DsecLayout m3ed = tum;
  m3ed.group = "prophesee/left";
  m3ed.write_ms_to_idx = false;
  t::writeDsecEvents(dir + "/dsec_events/seed_m3ed_40_events.h5", events, m3ed);
  if (H5Zfilter_avail(32001) > 0) {
    // Blosc fails (a mandatory filter: the chunk is not written) on chunks too small to compress: 1000 values.
    t::DsecLayout blosc = dsec;
    blosc.chunk = 1000;
    blosc.filter = 32001;
    blosc.filter_values = {0, 0, 0, 0, 5, 2, 5};  // level 5, bit shuffle, Zstd
    t::writeDsecEvents(dir + "/dsec_events/seed_blosc_zstd_2000_events.h5", t::syntheticDsecEvents(2000), blosc);
  }
  // Rectification maps of the harness's 8x6 sensor: a shift by half a pixel (some pixels leave the
  // sensor), and one of the wrong shape.
  const std::vector<float> shift = t::rectifyMapValues(8, 6, [](int x, int y) {
    return std::pair<float, float>(float(x) + 0.5f, float(y) - 0.4f);
  });
  t::writeRectifyMap(dir + "/dsec_rectify_map/seed_8x6_shift.h5", shift, {6, 8, 2});
  t::writeRectifyMap(dir + "/dsec_rectify_map/seed_wrong_shape.h5", shift, {8, 6, 2});
  return 0;
}
