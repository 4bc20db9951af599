// The value size a chunked dataset's data layout message declares (src/io/hdf5_layout.hpp), read from the
// file's bytes: for the object header and layout versions libhdf5 writes by default (1 and 3) and with the
// latest format (2 and 4), after a user block, and the corrupt layout the dsec_events fuzz harness found.
#include "../../src/io/hdf5_layout.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../../src/io/hdf5_handle.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"
#include "dsec_fixture.hpp"
#include "io_test_util.hpp"

namespace asynevo::io_detail {
namespace {

struct FileOptions {
  bool latest_format = false;  // object header version 2, layout message version 4
  hsize_t userblock = 0;
  int attributes = 0;  // attributes added after the dataset: its header continues in further chunks
};

FileOptions latestFormat(bool latest) {
  FileOptions options;
  options.latest_format = latest;
  return options;
}

// One dataset per type below, each of 100 values, chunked by 10 unless `contiguous`.
void writeFile(const std::string& path, const FileOptions& options) {
  const hid_t create = H5Pcreate(H5P_FILE_CREATE);
  if (options.userblock > 0) H5Pset_userblock(create, options.userblock);
  const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
  if (options.latest_format) H5Pset_libver_bounds(access, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, create, access);
  const hsize_t n = 100, chunk = 10;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const std::vector<uint64_t> values(n, 7);
  auto add = [&](const char* name, hid_t type, bool chunked) {
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (chunked) H5Pset_chunk(dcpl, 1, &chunk);
    const hid_t dataset = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    H5Dwrite(dataset, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    const hid_t scalar = H5Screate(H5S_SCALAR);
    for (int i = 0; i < options.attributes; ++i) {
      const std::string attribute = "attribute_" + std::to_string(i);
      const hid_t a = H5Acreate2(dataset, attribute.c_str(), H5T_STD_I64LE, scalar, H5P_DEFAULT, H5P_DEFAULT);
      H5Awrite(a, H5T_NATIVE_INT, &i);
      H5Aclose(a);
    }
    H5Sclose(scalar);
    H5Dclose(dataset);
    H5Pclose(dcpl);
  };
  add("u8", H5T_STD_U8LE, true);
  add("u16", H5T_STD_U16LE, true);
  add("f32", H5T_IEEE_F32LE, true);
  add("u64", H5T_STD_U64LE, true);
  add("contiguous", H5T_STD_U32LE, false);
  H5Sclose(space);
  H5Fclose(file);
  H5Pclose(access);
  H5Pclose(create);
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The value size h5ChunkValueSize reads for dataset `name`.
uint64_t valueSize(const std::string& path, const char* name) {
  const H5File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  const H5Dataset dataset(H5Dopen2(file.get(), name, H5P_DEFAULT));
  EXPECT_TRUE(dataset.valid()) << name;
  return h5ChunkValueSize(path, dataset.get(), name);
}

void expectTheTypesSizes(const std::string& path) {
  EXPECT_EQ(valueSize(path, "u8"), 1u);
  EXPECT_EQ(valueSize(path, "u16"), 2u);
  EXPECT_EQ(valueSize(path, "f32"), 4u);
  EXPECT_EQ(valueSize(path, "u64"), 8u);
  EXPECT_EQ(valueSize(path, "contiguous"), 0u);
}

TEST(Hdf5Layout, ReadsTheValueSizeOfDefaultFormatFiles) {
  const testing::TempDir dir;
  const std::string path = dir.file("default.h5");
  writeFile(path, {});
  expectTheTypesSizes(path);
}

TEST(Hdf5Layout, ReadsTheValueSizeOfLatestFormatFiles) {
  const testing::TempDir dir;
  const std::string path = dir.file("latest.h5");
  writeFile(path, latestFormat(true));
  ASSERT_NE(fileBytes(path).find("OHDR"), std::string::npos);  // version 2 object headers
  expectTheTypesSizes(path);
}

TEST(Hdf5Layout, AddressesCountFromTheEndOfAUserBlock) {
  const testing::TempDir dir;
  for (const bool latest : {false, true}) {
    const std::string path = dir.file(latest ? "latest.h5" : "default.h5");
    FileOptions options = latestFormat(latest);
    options.userblock = 1024;
    writeFile(path, options);
    expectTheTypesSizes(path);
  }
}

// With 6 attributes added, libhdf5 1.10.8 continues every chunked dataset's header and moves one layout
// message (of the 8) into a continuation chunk.
TEST(Hdf5Layout, HeadersContinuedInFurtherChunksAreFollowed) {
  const testing::TempDir dir;
  for (const bool latest : {false, true}) {
    const std::string path = dir.file(latest ? "latest.h5" : "default.h5");
    FileOptions options = latestFormat(latest);
    options.attributes = 6;
    writeFile(path, options);
    if (latest) {
      EXPECT_NE(fileBytes(path).find("OCHK"), std::string::npos);  // a version 2 continuation block
    }
    expectTheTypesSizes(path);
  }
}

TEST(Hdf5Layout, AValueSizeOtherThanTheTypesIsRejected) {
  const testing::TempDir dir;
  const std::string path = dir.file("default.h5");
  writeFile(path, {});
  const H5File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  const H5Dataset dataset(H5Dopen2(file.get(), "u16", H5P_DEFAULT));
  EXPECT_NO_THROW(h5CheckChunkValueSize(path, dataset.get(), "u16", 2));
  try {
    h5CheckChunkValueSize(path, dataset.get(), "u16", 4);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path +
                  ": dataset 'u16' holds values of 4 bytes but its chunk layout declares "
                  "values of 2 bytes (corrupt layout message?)");
  }
}

// Found by the dsec_events fuzz harness (2026-11-27): the layout message of events/t declares values of
// 0x444D8BE3 bytes instead of 4; libhdf5 1.10.8 then read a later packet from past the Blosc filter's
// 4000-byte chunk buffer. The DSEC reader now rejects the file when it opens it.
TEST(Hdf5Layout, TheCorruptLayoutTheFuzzerFoundIsAnInputError) {
  const std::string path = std::string(ASYNEVO_FUZZ_CORPUS_DIR) + "/dsec_events/regress_layout_value_size.h5";
  ReaderOptions options;
  options.width = 640;
  options.height = 480;
  options.size_origin = "--sensor";
  EXPECT_EQ(
      testing::errorOf(path, options),
      path +
          ": dataset 'events/t' holds values of 4 bytes but its chunk layout declares values of 1145932771 "
          "bytes (corrupt layout message?)");
}

}  // namespace
}  // namespace asynevo::io_detail
