#include "asynevo/io/groundtruth_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"
#include "mvsec_fixture.hpp"

namespace asynevo {
namespace {

using testing::dataPath;
using testing::TempDir;

// Row-major homogeneous pose: rotation of `angle` about z, translation (x, y, z).
std::array<double, 16> poseAboutZ(double angle, double x, double y, double z) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c, -s, 0, x, s, c, 0, y, 0, 0, 1, z, 0, 0, 0, 1};
}

TEST(MvsecGroundTruth, ReadsPosesAndTimes) {
  TempDir dir;
  const auto path = dir.file("indoor_flying1_gt.hdf5");
  testing::writeMvsecGroundTruth(path, {poseAboutZ(0, 1, 2, 3), poseAboutZ(M_PI / 2, 4, 5, 6)},
                                 {1504645177.5, 1504645177.55});
  const auto trajectory = readGroundTruth(path);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_NEAR(trajectory[1].t_ns - trajectory[0].t_ns, 50'000'000, 500);  // float64 s near 1.5e9: ~0.2 µs steps
  EXPECT_TRUE(trajectory[1].p_w_c.isApprox(Eigen::Vector3d(4, 5, 6)));
  const Eigen::Vector3d x_rotated = trajectory[1].q_w_c * Eigen::Vector3d::UnitX();
  EXPECT_NEAR((x_rotated - Eigen::Vector3d::UnitY()).norm(), 0, 1e-12);
}

TEST(MvsecGroundTruth, BadPosesNameTheRecord) {
  TempDir dir;
  const auto path = dir.file("bad_gt.hdf5");
  auto bent = poseAboutZ(0, 0, 0, 0);
  bent[0] = 2.0;  // not a rotation
  testing::writeMvsecGroundTruth(path, {poseAboutZ(0, 0, 0, 0), bent}, {1.0, 2.0});
  try {
    readMvsecGroundTruth(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": record 1: the rotation block is not a rotation matrix");
  }
  testing::writeMvsecGroundTruth(path, {poseAboutZ(0, 0, 0, 0), poseAboutZ(0, 0, 0, 0)}, {2.0, 1.0});
  EXPECT_THROW(readMvsecGroundTruth(path), InputError);
  testing::writeMvsecGroundTruth(path, {poseAboutZ(0, 0, 0, 0)}, {1.0, 2.0});
  EXPECT_THROW(readMvsecGroundTruth(path), InputError);
}

// A finite time beyond int64 nanoseconds (found 2026-11-26 by reading the reader after fuzzing): llround
// gave INT64_MIN for 1e20 s and a one-pose file was accepted with that time.
TEST(MvsecGroundTruth, TimeOutsideTheInt64RangeNamesTheRecord) {
  TempDir dir;
  const auto path = dir.file("far_gt.hdf5");
  testing::writeMvsecGroundTruth(path, {poseAboutZ(0, 0, 0, 0)}, {1e20});
  try {
    readMvsecGroundTruth(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": record 0: time 1e+20 s is out of range (|t| > 9e9 s)");
  }
}

// The mvsec_groundtruth fuzz finding of 2026-11-26 (fuzz/corpus/mvsec_groundtruth/regress_float_type_4gb.hdf5):
// pose_ts declared as a float type of 4278190088 bytes per value; H5Dread allocated 4 GB for the
// conversion (libFuzzer: out-of-memory). The type is checked before anything is read.
TEST(MvsecGroundTruth, ImplausibleValueTypeIsRejectedBeforeReading) {
  const std::string path =
      std::string(ASYNEVO_SOURCE_DIR) + "/fuzz/corpus/mvsec_groundtruth/regress_float_type_4gb.hdf5";
  try {
    readMvsecGroundTruth(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": dataset 'davis/left/pose_ts' does not hold 32- or 64-bit "
                                            "floating-point numbers (its values are 4278190088 bytes each; "
                                            "corrupt file?)");
  }
}

TEST(GroundTruth, TextFilesGoToTheTumReader) {
  const auto trajectory = readGroundTruth(dataPath("ecd/shapes_rotation/groundtruth.txt"));
  EXPECT_EQ(trajectory.size(), 11883u);
}

}  // namespace
}  // namespace asynevo
