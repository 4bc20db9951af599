// DSEC-style HDF5 event reader (format "dsec"): fixtures written from the layout description
// (tests/io/dsec_fixture.hpp), the variants, and every kind of bad input.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "dsec_fixture.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

// The Blosc tests need the HDF5 filter plugin (filter 32001), which CI installs; skip where it is missing.
#define SKIP_WITHOUT_BLOSC_PLUGIN()                                                                      \
  if (H5Zfilter_avail(32001) <= 0)                                                                       \
  GTEST_SKIP() << "the HDF5 Blosc filter plugin is not installed (Debian: hdf5-filter-plugin-blosc-serial)"

using testing::DsecEvents;
using testing::DsecLayout;
using testing::TempDir;
using testing::syntheticDsecEvents;
using testing::writeDsecEvents;

ReaderOptions vga(int packet_size = 65536) {
  ReaderOptions options;
  options.width = 640;
  options.height = 480;
  options.size_origin = "--sensor";
  options.packet_size = packet_size;
  return options;
}

void expectAsWritten(const std::vector<Event>& all, const DsecEvents& written, int64_t t_offset_us) {
  ASSERT_EQ(all.size(), written.t.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(all[i].t_ns, (written.t[i] + t_offset_us) * 1000) << i;
    ASSERT_EQ(all[i].x, written.x[i]) << i;
    ASSERT_EQ(all[i].y, written.y[i]) << i;
    ASSERT_EQ(all[i].polarity, written.p[i] == 1 ? 1 : -1) << i;
  }
}

TEST(DsecReader, ReadsTheDsecLayoutInPacketsWithTOffsetAndDetectsIt) {
  TempDir dir;
  const std::string path = dir.file("events.h5");
  const DsecEvents events = syntheticDsecEvents(2500);
  DsecLayout layout;
  layout.t_offset_us = 49'599'300'523;  // a DSEC-like start time (µs)
  writeDsecEvents(path, events, layout);
  auto reader = openEventReader(path, vga(333));  // --format auto
  EXPECT_EQ(reader->info().format, "dsec");
  EXPECT_EQ(reader->info().width, 640);
  EXPECT_EQ(reader->info().size_origin, "--sensor");
  EventPacket packet;
  std::vector<Event> all;
  while (reader->read(packet)) {
    EXPECT_LE(packet.size(), 333u);
    EXPECT_EQ(packet.first_index, all.size());
    all.insert(all.end(), packet.events.begin(), packet.events.end());
  }
  expectAsWritten(all, events, layout.t_offset_us);
  EXPECT_EQ(reader->stats().events, 2500u);
}

TEST(DsecReader, ReadsTumVieAndM3edVariants) {
  TempDir dir;
  const DsecEvents events = syntheticDsecEvents(100);
  DsecLayout tum;  // TUM-VIE: int64 µs, ms_to_idx, no t_offset
  tum.t_type = H5T_STD_I64LE;
  tum.write_t_offset = false;
  writeDsecEvents(dir.file("tum.h5"), events, tum);
  expectAsWritten(readAllEvents(dir.file("tum.h5"), vga()), events, 0);
  DsecLayout m3ed;  // M3ED: prophesee/left/{x,y,t,p}, int64 µs
  m3ed.group = "prophesee/left";
  m3ed.t_type = H5T_STD_I64LE;
  m3ed.write_t_offset = false;
  m3ed.write_ms_to_idx = false;
  writeDsecEvents(dir.file("m3ed_data.h5"), events, m3ed);
  auto reader = openEventReader(dir.file("m3ed_data.h5"), vga());
  EXPECT_EQ(reader->info().format, "dsec");
  expectAsWritten(readAllEvents(dir.file("m3ed_data.h5"), vga()), events, 0);
}

TEST(DsecReader, DatasetFolderFindsEventsH5AndFormatFilters) {
  TempDir dir;
  writeDsecEvents(dir.file("events.h5"), syntheticDsecEvents(10));
  EXPECT_EQ(resolveDataset(dir.path().string()).events, dir.file("events.h5"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "dsec").events, dir.file("events.h5"));
}

TEST(DsecReader, WithoutASensorSizeAsksForOne) {
  TempDir dir;
  writeDsecEvents(dir.file("events.h5"), syntheticDsecEvents(10));
  const std::string message = testing::errorOf(dir.file("events.h5"), ReaderOptions{});
  EXPECT_NE(message.find("DSEC-style HDF5 files store no sensor size"), std::string::npos) << message;
  EXPECT_NE(message.find("--sensor WxH"), std::string::npos) << message;
}

TEST(DsecReader, MvsecFilesAreStillDetectedAsMvsec) {
  TempDir dir;
  // An HDF5 file without any event group goes to the MVSEC reader, which names what it expected.
  DsecLayout other;
  other.group = "something/else";
  writeDsecEvents(dir.file("x.h5"), syntheticDsecEvents(5), other);
  EXPECT_NE(testing::errorOf(dir.file("x.h5"), vga()).find("no dataset 'davis/left/events'"), std::string::npos);
}

TEST(DsecReader, MissingDatasetsAndMismatchedLengths) {
  TempDir dir;
  DsecLayout no_p;
  no_p.skip = {"p"};
  writeDsecEvents(dir.file("a.h5"), syntheticDsecEvents(10), no_p);
  EXPECT_EQ(testing::errorOf(dir.file("a.h5"), vga()), dir.file("a.h5") + ": missing dataset 'events/p'");
  DsecEvents short_y = syntheticDsecEvents(10);
  short_y.y.resize(9);
  writeDsecEvents(dir.file("b.h5"), short_y);
  EXPECT_EQ(testing::errorOf(dir.file("b.h5"), vga()),
            dir.file("b.h5") + ": datasets 'events/x' (10 values) and 'events/y' (9 values) differ in length: every "
                               "event needs all four fields (truncated or corrupt file?)");
}

TEST(DsecReader, WrongDtypeIsNamed) {
  TempDir dir;
  DsecLayout float_t;
  float_t.t_type = H5T_IEEE_F64LE;
  float_t.write_ms_to_idx = false;
  writeDsecEvents(dir.file("f.h5"), syntheticDsecEvents(10), float_t);
  EXPECT_EQ(testing::errorOf(dir.file("f.h5"), vga()),
            dir.file("f.h5") + ": dataset 'events/t' does not hold integers of 1, 2, 4 or 8 bytes (DSEC: x, y "
                               "uint16, p uint8, t uint32 microseconds)");
}

TEST(DsecReader, BadEventsNameTheRecord) {
  TempDir dir;
  DsecEvents unsorted = syntheticDsecEvents(50);
  unsorted.t[20] = 1;
  DsecLayout no_index;
  no_index.write_ms_to_idx = false;
  writeDsecEvents(dir.file("u.h5"), unsorted, no_index);
  const std::string u = testing::errorOf(dir.file("u.h5"), vga(16));
  EXPECT_EQ(u.rfind(dir.file("u.h5") + ": record 20: time goes backwards by", 0), 0u) << u;

  DsecEvents outside = syntheticDsecEvents(50);
  outside.x[33] = 640;
  writeDsecEvents(dir.file("o.h5"), outside);
  const std::string o = testing::errorOf(dir.file("o.h5"), vga(16));
  EXPECT_EQ(o.rfind(dir.file("o.h5") + ": record 33: pixel (640, 231) is outside the 640x480 sensor (size from --sensor)",
                    0),
            0u)
      << o;

  DsecEvents polarity = syntheticDsecEvents(50);
  polarity.p[7] = 2;
  writeDsecEvents(dir.file("p.h5"), polarity);
  EXPECT_EQ(testing::errorOf(dir.file("p.h5"), vga()), dir.file("p.h5") + ": record 7: polarity 2 is not one of 0, 1, -1");
}

TEST(DsecReader, TimeOutOfRangeWithTOffset) {
  TempDir dir;
  DsecLayout layout;
  layout.t_type = H5T_STD_I64LE;
  layout.write_ms_to_idx = false;
  layout.t_offset_us = 9'000'000'000'000'000;
  DsecEvents events = syntheticDsecEvents(5);
  events.t[3] = 1'000'000'000'000'000;
  writeDsecEvents(dir.file("r.h5"), events, layout);
  EXPECT_EQ(testing::errorOf(dir.file("r.h5"), vga()),
            dir.file("r.h5") + ": record 3: time 1000000000000000 µs (+ t_offset 9000000000000000 µs) is out of range");
}

TEST(DsecReader, MsToIdxIsCheckedAgainstTheEvents) {
  TempDir dir;
  const DsecEvents events = syntheticDsecEvents(1000);  // t = 3 .. 6996 µs: ms 0..6
  DsecLayout wrong;
  wrong.ms_to_idx = testing::dsecMsToIdx(events.t);
  ASSERT_EQ(wrong.ms_to_idx.size(), 7u);
  wrong.ms_to_idx[4] += 1;
  writeDsecEvents(dir.file("w.h5"), events, wrong);
  const std::string w = testing::errorOf(dir.file("w.h5"), vga(100));
  const uint64_t first_at_4ms = testing::dsecMsToIdx(events.t)[4];
  EXPECT_EQ(w, fmt::format("{}: record {}: ms_to_idx[4] is {}, but the first event at or after 4 ms (t before "
                           "t_offset) is this one: the index does not match the events (corrupt file?)",
                           dir.file("w.h5"), first_at_4ms, first_at_4ms + 1));
  DsecLayout longer;  // entries past the last event must hold the event count
  longer.ms_to_idx = testing::dsecMsToIdx(events.t);
  longer.ms_to_idx.push_back(1000);
  longer.ms_to_idx.push_back(999);
  writeDsecEvents(dir.file("l.h5"), events, longer);
  EXPECT_EQ(testing::errorOf(dir.file("l.h5"), vga()),
            dir.file("l.h5") + ": ms_to_idx[8] is 999, but no event is at or after 8 ms: it must be the event "
                               "count 1000 (corrupt file?)");
}

TEST(DsecReader, TruncatedAndCorruptFilesAreErrorsNotCrashes) {
  TempDir dir;
  const std::string good = dir.file("good.h5");
  writeDsecEvents(good, syntheticDsecEvents(3000));
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int errors = 0;
  for (std::size_t keep : {bytes.size() / 10, bytes.size() / 3, bytes.size() / 2, bytes.size() * 9 / 10,
                           bytes.size() - 1}) {
    const std::string cut = dir.write("cut.h5", bytes.substr(0, keep));
    ReaderOptions options = vga();
    options.format = "dsec";
    errors += testing::errorOf(cut, options).empty() ? 0 : 1;
  }
  EXPECT_EQ(errors, 5);
  // Flipped bytes in the data area: an error or (if only values changed and stayed valid) events, never a crash.
  for (std::size_t at = bytes.size() / 4; at < bytes.size(); at += bytes.size() / 16) {
    std::string corrupt = bytes;
    for (std::size_t k = at; k < std::min(bytes.size(), at + 64); ++k) corrupt[k] = static_cast<char>(~corrupt[k]);
    const std::string path = dir.write("corrupt.h5", corrupt);
    try {
      readAllEvents(path, vga());
    } catch (const InputError&) {
    }
  }
}

// A compressed dataset whose declared length has no chunks behind it (a corrupt length, or a writer killed
// before the end) would read as fill values: every chunk must be stored.
TEST(DsecReader, CompressedDatasetWithUnstoredChunksIsRejected) {
  TempDir dir;
  const std::string path = dir.file("partial.h5");
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hsize_t n = 3000, chunk = 1000, written = 1000;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(dcpl, 1, &chunk);
  H5Pset_deflate(dcpl, 1);
  const std::vector<int64_t> values(written, 1);
  for (const char* name : {"events/x", "events/y", "events/t", "events/p"}) {
    const hid_t set = H5Dcreate2(file, name, H5T_STD_U16LE, space, lcpl, dcpl, H5P_DEFAULT);
    const hid_t file_space = H5Dget_space(set);
    const hsize_t start = 0;
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, &start, nullptr, &written, nullptr);
    const hid_t memory_space = H5Screate_simple(1, &written, nullptr);
    H5Dwrite(set, H5T_NATIVE_INT64, memory_space, file_space, H5P_DEFAULT, values.data());
    H5Sclose(memory_space);
    H5Sclose(file_space);
    H5Dclose(set);
  }
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Pclose(lcpl);
  H5Fclose(file);
  EXPECT_EQ(testing::errorOf(path, vga()), path + ": dataset 'events/x' declares 3000 values in 3 chunks of 1000 but stores 1 "
                                           "chunks (truncated or corrupt file?)");
}

// Found by the dsec_events fuzz harness (2026-11-27): a corrupt layout message declares chunks far larger than
// the fixed-size Blosc-compressed dataset; libhdf5 1.10 read past the decompressed chunk on a later packet.
TEST(DsecReader, AChunkLargerThanAFixedSizeDatasetIsRejected) {
  const std::string corpus = std::string(ASYNEVO_FUZZ_CORPUS_DIR) + "/dsec_events/";
  const std::string x = corpus + "regress_chunk_larger_than_dataset_x.h5";
  EXPECT_EQ(testing::errorOf(x, vga()), x + ": dataset 'events/x' declares chunks of 1207960552 values, more than "
                                            "its fixed size of 2000 values (corrupt layout?)");
  const std::string p = corpus + "regress_chunk_larger_than_dataset_p.h5";
  EXPECT_EQ(testing::errorOf(p, vga()), p + ": dataset 'events/p' declares chunks of 3774874600 values, more than "
                                            "its fixed size of 2000 values (corrupt layout?)");
}

// A dataset compressed with a filter this HDF5 library cannot load: the message names the remedy. The filter
// is registered only to write the file, then unregistered (plugin loading off, so it stays unavailable).
std::size_t identityFilter(unsigned, std::size_t, const unsigned[], std::size_t nbytes, std::size_t*, void**) {
  return nbytes;
}

TEST(DsecReader, UnavailableFilterNamesThePackageOrPluginPath) {
  TempDir dir;
  constexpr H5Z_filter_t kId = 32999;
  const H5Z_class2_t filter_class = {H5Z_CLASS_T_VERS, kId, 1, 1, "test filter", nullptr, nullptr,
                                     &identityFilter};
  ASSERT_GE(H5Zregister(&filter_class), 0);
  DsecLayout layout;
  layout.filter = kId;
  writeDsecEvents(dir.file("z.h5"), syntheticDsecEvents(20), layout);
  ASSERT_GE(H5Zunregister(kId), 0);
  unsigned state = 0;
  H5PLget_loading_state(&state);
  H5PLset_loading_state(0);
  const std::string message = testing::errorOf(dir.file("z.h5"), vga());
  H5PLset_loading_state(state);
  EXPECT_EQ(message, dir.file("z.h5") + ": dataset 'events/x' is compressed with HDF5 filter 32999 ('test filter'), "
                                        "which this HDF5 library cannot load: install an HDF5 filter plugin for it "
                                        "(Debian: hdf5-filter-plugin, hdf5-filter-plugin-blosc-serial; or the plugins "
                                        "of the hdf5plugin Python package) and set HDF5_PLUGIN_PATH to its folder");
}

// DSEC's own compression: Blosc (HDF5 filter 32001) with its Zstd codec, bit shuffle. Needs the Debian package
// hdf5-filter-plugin-blosc-serial.
// Found by the dsec_events fuzz harness (2026-11-27): the Blosc header of the second chunk of events/p
// declares 0x76650030 compressed bytes for the 48 it stores; libblosc bounded its reads by that and read far
// past the chunk on the second packet. Each chunk's header is now compared with the chunk as stored first.
TEST(DsecReader, ABloscChunkWhoseHeaderMisstatesItsSizeIsRejected) {
  SKIP_WITHOUT_BLOSC_PLUGIN();
  const std::string path = std::string(ASYNEVO_FUZZ_CORPUS_DIR) + "/dsec_events/regress_blosc_cbytes.h5";
  EXPECT_EQ(testing::errorOf(path, vga(1000)),
            path + ": record 1000: dataset 'events/p': the chunk's Blosc header declares 1000 bytes compressed into "
                   "1986330672, but the chunk holds 1000 bytes of values and stores 48 (corrupt chunk?)");
}

// The dsec_events fuzz findings of 2026-11-28 (fuzz/corpus/dsec_events/regress_chunk_index_size_*.h5): a
// chunk index that lists one size for a Blosc chunk while libhdf5's chunk lookup, which H5Dread_chunk
// reads by, says another; the check's read ran past its buffer (heap-buffer-overflow under ASan). Now
// an InputError naming the dataset and the record.
TEST(DsecReader, AChunkIndexThatMisstatesAChunksSizeIsRejected) {
  SKIP_WITHOUT_BLOSC_PLUGIN();
  for (int i = 1; i <= 3; ++i) {
    const std::string path =
        std::string(ASYNEVO_FUZZ_CORPUS_DIR) + "/dsec_events/regress_chunk_index_size_" + std::to_string(i) + ".h5";
    const std::string error = testing::errorOf(path, vga(256));
    EXPECT_NE(error.find(path + ": record "), std::string::npos) << error;
    EXPECT_NE(error.find("(corrupt chunk index?)"), std::string::npos) << error;
  }
}

// The dsec_events fuzz finding of 2026-11-28 (fuzz/corpus/dsec_events/regress_chunk_listed_absent.h5):
// the chunk index lists the first chunk of 'events/x' as not stored (0 bytes: fill values), so the Blosc
// check passed it, while libhdf5's chunk lookup finds 229 bytes there; H5Dread decompressed them into
// 2000 bytes and copied past them (heap-buffer-overflow in H5VM_memcpyvv). Now an InputError.
TEST(DsecReader, AChunkTheIndexListsAsAbsentButTheLookupFindsIsRejected) {
  SKIP_WITHOUT_BLOSC_PLUGIN();
  const std::string path = std::string(ASYNEVO_FUZZ_CORPUS_DIR) + "/dsec_events/regress_chunk_listed_absent.h5";
  EXPECT_EQ(testing::errorOf(path, vga(256)),
            path + ": record 0: dataset 'events/x': its chunk index lists 0 bytes for the chunk, the chunk lookup "
                   "229 (corrupt chunk index?)");
}

TEST(DsecReader, ReadsBloscZstdCompressedFiles) {
  constexpr H5Z_filter_t kBlosc = 32001;
  SKIP_WITHOUT_BLOSC_PLUGIN();
  TempDir dir;
  const DsecEvents events = syntheticDsecEvents(20000);
  DsecLayout layout;
  layout.filter = kBlosc;
  // cd_values 0-3 are filled in by the filter's set_local; 4 level, 5 shuffle (2 = bit), 6 codec (5 = Zstd).
  layout.filter_values = {0, 0, 0, 0, 5, 2, 5};
  layout.chunk = 4096;
  layout.t_offset_us = 1'000'000;
  writeDsecEvents(dir.file("events.h5"), events, layout);
  {  // the file really is Blosc-compressed
    const hid_t file = H5Fopen(dir.file("events.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t t = H5Dopen2(file, "events/t", H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(t);
    ASSERT_EQ(H5Pget_nfilters(dcpl), 1);
    unsigned flags = 0;
    std::size_t values = 0;
    EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, &values, nullptr, 0, nullptr, nullptr), kBlosc);
    EXPECT_LT(H5Dget_storage_size(t), events.t.size() * 4);  // smaller than the raw uint32 values
    H5Pclose(dcpl);
    H5Dclose(t);
    H5Fclose(file);
  }
  expectAsWritten(readAllEvents(dir.file("events.h5"), vga(3000)), events, layout.t_offset_us);
  // Without the plugin (unregistered, plugin loading off) the message names the Debian package.
  ASSERT_GE(H5Zunregister(kBlosc), 0);
  unsigned state = 0;
  H5PLget_loading_state(&state);
  H5PLset_loading_state(0);
  const std::string message = testing::errorOf(dir.file("events.h5"), vga());
  H5PLset_loading_state(state);
  EXPECT_EQ(message, dir.file("events.h5") + ": dataset 'events/x' is compressed with HDF5 filter 32001 ('blosc'), "
                                             "which this HDF5 library cannot load: install the Debian package "
                                             "hdf5-filter-plugin-blosc-serial (sudo apt-get install "
                                             "hdf5-filter-plugin-blosc-serial)");
}

}  // namespace
}  // namespace asynevo
