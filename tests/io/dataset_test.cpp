// Which file of a dataset folder holds the events (include/asynevo/io/dataset.hpp).
#include "asynevo/io/dataset.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

std::string errorOf(const std::string& path, const std::string& format = "auto") {
  try {
    resolveDataset(path, format);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Dataset, FindsEveryKnownEventFileName) {
  for (const char* name : {"events.txt", "events.aevt", "events.raw", "recording_2024-01-01_10-00-00.raw",
                           "events.dat", "moorea_td.dat", "rec_cd.dat", "dvSave-2023_01_01.aedat4", "indoor_flying1_data.hdf5"}) {
    TempDir dir;
    dir.write(name, "x");
    dir.write("calib.txt", "1 1 1 1 0 0 0 0 0\n");
    dir.write("notes.dat", "not events");  // neither events.dat nor *_td.dat / *_cd.dat
    const DatasetFiles files = resolveDataset(dir.path().string());
    EXPECT_EQ(files.events, dir.file(name)) << name;
    EXPECT_EQ(files.calibration, dir.file("calib.txt")) << name;
    EXPECT_FALSE(files.sensor) << name;
  }
}

TEST(Dataset, SeveralEventFilesAreAnErrorListingThem) {
  TempDir dir;
  dir.write("events.txt", "x");
  dir.write("events.raw", "x");
  dir.write("b_td.dat", "x");
  EXPECT_EQ(errorOf(dir.path().string()),
            dir.path().string() +
                ": several event files in this folder (b_td.dat, events.raw, events.txt): pass the one to read as "
                "--dataset FOLDER/FILE, or choose the format with --format");
  // --format keeps only its own files.
  EXPECT_EQ(resolveDataset(dir.path().string(), "ecd").events, dir.file("events.txt"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "evt3").events, dir.file("events.raw"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "evt2").events, dir.file("events.raw"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "dat").events, dir.file("b_td.dat"));
  EXPECT_EQ(errorOf(dir.path().string(), "mvsec"),
            dir.path().string() + ": no event file in this folder for --format mvsec (expected " + kEventFileNames +
                "; or pass the event file itself as --dataset)");
  dir.write("a.raw", "x");
  EXPECT_NE(errorOf(dir.path().string(), "evt3").find("several event files in this folder for --format evt3 (a.raw, "
                                                      "events.raw)"),
            std::string::npos);
  // An unknown --format does not filter (openEventReader names it as unknown).
  EXPECT_EQ(resolveDataset(dir.file("events.raw"), "foo").events, dir.file("events.raw"));
  EXPECT_NE(errorOf(dir.path().string(), "foo").find("several event files in this folder ("), std::string::npos);
  // A file given as --dataset is the choice, whatever else the folder holds.
  EXPECT_EQ(resolveDataset(dir.file("events.raw")).events, dir.file("events.raw"));
}

TEST(Dataset, ConvertedAevtIsTakenUnlessTheFormatNamesAnother) {
  TempDir dir;
  dir.write("events.txt", "x");
  dir.write("events.aevt", "x");
  EXPECT_EQ(resolveDataset(dir.path().string()).events, dir.file("events.aevt"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "aevt").events, dir.file("events.aevt"));
  EXPECT_EQ(resolveDataset(dir.path().string(), "ecd").events, dir.file("events.txt"));
}

TEST(Dataset, EmptyFolderNamesTheExpectedFiles) {
  TempDir dir;
  dir.write("readme.md", "x");
  std::filesystem::create_directory(dir.file("events.raw"));  // a folder is not an event file
  EXPECT_EQ(errorOf(dir.path().string()), dir.path().string() + ": no event file in this folder (expected " +
                                              kEventFileNames + "; or pass the event file itself as --dataset)");
}

TEST(Dataset, FindsSensorYaml) {
  TempDir dir;
  dir.write("events.txt", "x");
  dir.write("sensor.yaml", "width: 346\nheight: 260\n");
  EXPECT_EQ(resolveDataset(dir.path().string()).sensor, dir.file("sensor.yaml"));
  EXPECT_EQ(resolveDataset(dir.file("events.txt")).sensor, dir.file("sensor.yaml"));
}

}  // namespace
}  // namespace asynevo
