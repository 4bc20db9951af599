#include "asynevo/core/error.hpp"

#include <gtest/gtest.h>

namespace asynevo {
namespace {

TEST(InputError, NamesFileAndLine) {
  const InputError e = InputError::atLine("data/events.txt", 17, "expected 4 fields, found 3");
  EXPECT_STREQ(e.what(), "data/events.txt:17: expected 4 fields, found 3");
  EXPECT_EQ(e.file(), "data/events.txt");
  EXPECT_EQ(e.location(), 17u);
  EXPECT_EQ(e.locationKind(), InputError::LocationKind::kLine);
  EXPECT_EQ(e.message(), "expected 4 fields, found 3");
}

TEST(InputError, NamesFileAndRecord) {
  const InputError e = InputError::atRecord("seq_data.hdf5", 42, "x = 400 outside the 346x260 sensor");
  EXPECT_STREQ(e.what(), "seq_data.hdf5: record 42: x = 400 outside the 346x260 sensor");
  EXPECT_EQ(e.locationKind(), InputError::LocationKind::kRecord);
}

TEST(InputError, NamesFileAndByteOffset) {
  const InputError e = InputError::atByte("rec.raw", 1234, "unknown EVT 3.0 word type 0001");
  EXPECT_STREQ(e.what(), "rec.raw: byte 1234: unknown EVT 3.0 word type 0001");
  EXPECT_EQ(e.locationKind(), InputError::LocationKind::kByte);
  EXPECT_EQ(e.location(), 1234u);
}

TEST(InputError, FileOnly) {
  const InputError e("calib.txt", "cannot open file");
  EXPECT_STREQ(e.what(), "calib.txt: cannot open file");
  EXPECT_EQ(e.locationKind(), InputError::LocationKind::kNone);
}

}  // namespace
}  // namespace asynevo
