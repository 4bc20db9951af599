#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "io_test_util.hpp"
#include "mvsec_fixture.hpp"

namespace asynevo {
namespace {

using testing::TempDir;
using testing::writeMvsecEvents;

std::vector<std::array<double, 4>> syntheticRows(int n) {
  std::vector<std::array<double, 4>> rows;
  for (int i = 0; i < n; ++i)
    rows.push_back({double(i % 346), double((i * 7) % 260), 1504645177.0 + i * 1e-6, (i % 3 == 0) ? 1.0 : -1.0});
  return rows;
}

TEST(MvsecReader, ReadsTheLayoutInChunksAndDetectsTheFormat) {
  TempDir dir;
  const auto path = dir.file("indoor_flying1_data.hdf5");
  writeMvsecEvents(path, syntheticRows(2500));
  ReaderOptions options;
  options.packet_size = 1000;
  auto reader = openEventReader(path, options);
  EXPECT_EQ(reader->info().format, "mvsec");
  EXPECT_EQ(reader->info().width, 346);
  EXPECT_EQ(reader->info().height, 260);
  EventPacket packet;
  std::vector<Event> all;
  while (reader->read(packet)) {
    EXPECT_LE(packet.size(), 1000u);
    all.insert(all.end(), packet.events.begin(), packet.events.end());
  }
  ASSERT_EQ(all.size(), 2500u);
  EXPECT_EQ(all[3].x, 3);
  EXPECT_EQ(all[3].y, 21);
  EXPECT_EQ(all[3].polarity, 1);
  EXPECT_EQ(all[4].polarity, -1);
  // float64 seconds around 1.5e9 carry ~0.2 µs resolution: the reader rounds to the nearest ns.
  EXPECT_NEAR(all[2499].t_ns - all[0].t_ns, 2'499'000, 500);
}

TEST(MvsecReader, DatasetFolderFindsDataFile) {
  TempDir dir;
  writeMvsecEvents(dir.file("indoor_flying1_data.hdf5"), syntheticRows(10));
  const DatasetFiles files = resolveDataset(dir.path().string());
  EXPECT_EQ(files.events, dir.file("indoor_flying1_data.hdf5"));
}

void expectRecordError(const std::vector<std::array<double, 4>>& rows, const std::string& message) {
  TempDir dir;
  const auto path = dir.file("bad_data.hdf5");
  writeMvsecEvents(path, rows);
  try {
    readAllEvents(path);
    ADD_FAILURE() << "no error, expected " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": " + message);
  }
}

TEST(MvsecReader, BadRecordsNameTheRecord) {
  expectRecordError({{1, 1, 0.1, 1}, {1, 1, std::nan(""), 1}}, "record 1: non-finite value (NaN or inf)");
  expectRecordError({{400, 1, 0.1, 1}}, "record 0: pixel (400, 1) is outside the 346x260 sensor (size from the MVSEC default, a DAVIS346); "
                    "set the sensor size with --sensor WxH, a sensor.yaml (width: W, height: H) in the dataset folder "
                    "or a sensor: block in the configuration");
  expectRecordError({{1, 1, 0.1, 5}}, "record 0: polarity 5 is not one of 0, 1, -1");
  expectRecordError({{1, 1, 0.2, 1}, {1, 1, 0.1, 1}},
                    "record 1: time goes backwards by 100000000 ns (tolerance input.max_time_reversal_us = 0); "
                    "the events must be sorted by time");
  expectRecordError({{1.5, 1, 0.1, 1}}, "record 0: x, y and p must be whole numbers");
}

TEST(MvsecReader, WrongLayoutsAreRejected) {
  TempDir dir;
  const auto other = dir.file("other.hdf5");
  writeMvsecEvents(other, syntheticRows(3), "davis/right/events");
  try {
    openEventReader(other);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              other + ": no dataset 'davis/left/events' (not an MVSEC *_data.hdf5 file?)");
  }
}

TEST(MvsecReader, TruncatedFileIsAnErrorNotACrash) {
  TempDir dir;
  const auto path = dir.file("trunc_data.hdf5");
  writeMvsecEvents(path, syntheticRows(5000));
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  EXPECT_THROW(readAllEvents(path), InputError);
}

TEST(MvsecReader, EmptyEventTableYieldsNoEvents) {
  TempDir dir;
  const auto path = dir.file("empty_data.hdf5");
  writeMvsecEvents(path, {});
  EXPECT_TRUE(readAllEvents(path).empty());
}

// A dataset that declares far more rows than the file stores (no chunk or block allocated: HDF5 reads
// fill values) was read as 100 million events of pixel (0, 0) at t = 0, one packet at a time; it is
// rejected before anything is read (found 2026-11-26 with the mvsec_groundtruth fuzz finding's fix).
TEST(MvsecReader, RowsTheFileDoesNotStoreAreRejected) {
  TempDir dir;
  const auto path = dir.file("hollow_data.hdf5");
  {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    const hsize_t dims[2] = {100000000, 4};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_LATE);  // never written: no storage in the file
    const hid_t dataset = H5Dcreate2(file, "davis/left/events", H5T_IEEE_F64LE, space, lcpl, dcpl, H5P_DEFAULT);
    H5Dclose(dataset);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Pclose(lcpl);
    H5Fclose(file);
  }
  const std::string expected =
      path + ": dataset 'davis/left/events' declares 400000000 values of 8 bytes, more than the " +
      std::to_string(std::filesystem::file_size(path)) + "-byte file holds (corrupt file?)";
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
}

// The mvsec_events fuzz finding of 2026-11-26 (fuzz/corpus/mvsec_events/regress_chunk_smaller_than_declared.hdf5):
// a chunked 40×4 float64 dataset whose chunk index stores fewer bytes than the chunk; libhdf5 1.10 copied
// 1280 bytes out of an 8-byte buffer inside H5Dread (ASan heap-buffer-overflow). Rejected before reading.
TEST(MvsecReader, StoredBytesFewerThanDeclaredAreRejectedBeforeReading) {
  const std::string path =
      std::string(ASYNEVO_SOURCE_DIR) + "/fuzz/corpus/mvsec_events/regress_chunk_smaller_than_declared.hdf5";
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": dataset 'davis/left/events' declares 160 values of 8 bytes (1280 "
                                            "bytes) but stores 0 bytes (corrupt chunk index or layout?)");
  }
}

// The second one (regress_chunk_larger_than_stored.hdf5): the layout message says 40x65 chunks for a 40x4
// dataset that stores 1280 bytes; libhdf5 read 32 bytes past a 1288-byte buffer.
TEST(MvsecReader, ChunkLargerThanTheStoredBytesIsRejectedBeforeReading) {
  const std::string path =
      std::string(ASYNEVO_SOURCE_DIR) + "/fuzz/corpus/mvsec_events/regress_chunk_larger_than_stored.hdf5";
  try {
    openEventReader(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": dataset 'davis/left/events' stores 1280 bytes, not a whole number "
                                            "of its chunks (40x65 values of 8 bytes each; corrupt chunk index or "
                                            "layout?)");
  }
}

}  // namespace
}  // namespace asynevo
