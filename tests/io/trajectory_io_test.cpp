#include "asynevo/io/trajectory_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "asynevo/core/error.hpp"

namespace asynevo {
namespace {

namespace fs = std::filesystem;

class TrajectoryIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("asynevo_trajio_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& content) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << content;
    return path;
  }

  /// Expects reading `content` as TUM to fail at `line` with a message containing `fragment`.
  void expectTumError(const std::string& content, uint64_t line, const std::string& fragment) {
    const std::string path = write("bad.txt", content);
    try {
      readTumTrajectory(path);
      ADD_FAILURE() << "no error for:\n" << content;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.location(), line) << e.what();
      EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
    }
  }

  fs::path dir_;
};

TEST_F(TrajectoryIo, ReadsTumWithCommentsAndExactTimes) {
  const std::string path = write("traj.txt",
                                 "# timestamp tx ty tz qx qy qz qw\n"
                                 "\n"
                                 "0.021819287 4.5 1.5 1.4 0 0 0 1\n"
                                 "1.5\t1 2 3  0.5 0.5 0.5 0.5\r\n");
  TrajectoryReadReport report;
  const StampedTrajectory traj = readTumTrajectory(path, &report);
  ASSERT_EQ(traj.size(), 2u);
  EXPECT_EQ(traj[0].t_ns, 21'819'287);
  EXPECT_EQ(traj[1].t_ns, 1'500'000'000);
  EXPECT_EQ(traj[0].p_w_c, Eigen::Vector3d(4.5, 1.5, 1.4));
  EXPECT_EQ(traj[1].p_w_c, Eigen::Vector3d(1, 2, 3));
  // w last in the file; Eigen stores (x, y, z, w) in coeffs().
  EXPECT_DOUBLE_EQ(traj[0].q_w_c.w(), 1.0);
  EXPECT_DOUBLE_EQ(traj[1].q_w_c.x(), 0.5);
  EXPECT_DOUBLE_EQ(traj[1].q_w_c.w(), 0.5);
  EXPECT_EQ(report.records, 2u);
  EXPECT_EQ(report.skipped_lines, 2u);
  EXPECT_EQ(report.normalized_quaternions, 0u);
}

TEST_F(TrajectoryIo, ReadsRealEcdGroundTruth) {
  TrajectoryReadReport report;
  const StampedTrajectory gt = readEcdGroundTruth(
      std::string(ASYNEVO_SOURCE_DIR) + "/tests/data/ecd/shapes_rotation/groundtruth.txt", &report);
  ASSERT_EQ(gt.size(), 11883u);
  EXPECT_EQ(gt.front().t_ns, 21'819'287);
  EXPECT_EQ(gt.back().t_ns, 59'807'415'760);
  EXPECT_NEAR(gt.front().p_w_c.x(), 4.46142292115, 1e-12);
  EXPECT_NEAR(gt.front().q_w_c.w(), -0.477546305131, 1e-9);
  EXPECT_NEAR(gt.back().q_w_c.x(), 0.651278527057, 1e-9);
  EXPECT_EQ(report.normalized_quaternions, 0u);
  for (const StampedPose& pose : gt) EXPECT_NEAR(pose.q_w_c.norm(), 1.0, 1e-12);
}

TEST_F(TrajectoryIo, WriteThenReadIsExact) {
  StampedTrajectory traj;
  for (int i = 0; i < 5; ++i) {
    StampedPose pose;
    pose.t_ns = 1'000'000'007LL * i + 3;
    pose.p_w_c = Eigen::Vector3d(0.1 * i, -1.0 / 3.0, 1e-7 * i);
    pose.q_w_c = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    traj.push_back(pose);
  }
  const std::string path = (dir_ / "out.txt").string();
  writeTumTrajectory(path, traj, "estimate\nt tx ty tz qx qy qz qw");
  const StampedTrajectory back = readTumTrajectory(path);
  ASSERT_EQ(back.size(), traj.size());
  for (std::size_t i = 0; i < traj.size(); ++i) {
    EXPECT_EQ(back[i].t_ns, traj[i].t_ns);
    EXPECT_EQ(back[i].p_w_c, traj[i].p_w_c);  // shortest round-trip printing is exact
    EXPECT_NEAR(back[i].q_w_c.angularDistance(traj[i].q_w_c), 0.0, 1e-12);
  }
}

TEST_F(TrajectoryIo, VelocitiesRoundTrip) {
  std::vector<StampedTwist> twists(3);
  for (int i = 0; i < 3; ++i) {
    twists[i].t_ns = 20'000'000LL * i;
    twists[i].v_c = Eigen::Vector3d(i, 0.5, -0.25);
    twists[i].w_c = Eigen::Vector3d(0.1, -0.2 * i, 0.3);
  }
  const std::string path = (dir_ / "velocities.txt").string();
  writeVelocities(path, twists);
  const auto back = readVelocities(path);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[2].t_ns, 40'000'000);
  EXPECT_EQ(back[2].v_c, twists[2].v_c);
  EXPECT_EQ(back[2].w_c, twists[2].w_c);
  EXPECT_THROW(readTumTrajectory(path), InputError);  // 7 fields are not a pose
}

TEST_F(TrajectoryIo, NonUnitQuaternionIsNormalizedAndCounted) {
  const std::string path = write("traj.txt",
                                 "0 0 0 0 0 0 0 2\n"
                                 "1 0 0 0 0 0 0 1.0000001\n"
                                 "2 0 0 0 0 3 0 4\n");
  TrajectoryReadReport report;
  const StampedTrajectory traj = readTumTrajectory(path, &report);
  EXPECT_EQ(report.normalized_quaternions, 2u);  // 1e-7 off is within tolerance
  EXPECT_EQ(report.first_normalized_line, 1u);
  EXPECT_DOUBLE_EQ(report.max_quaternion_norm_error, 4.0);
  EXPECT_DOUBLE_EQ(traj[0].q_w_c.w(), 1.0);
  EXPECT_DOUBLE_EQ(traj[2].q_w_c.y(), 0.6);
  EXPECT_DOUBLE_EQ(traj[2].q_w_c.w(), 0.8);
}

// Components so large that squaring them overflows (found 2026-11-26 by the tum_trajectory fuzz harness):
// the norm was inf, the quaternion became 0 / inf = 0 and was accepted. Now normalized like any other.
TEST_F(TrajectoryIo, HugeQuaternionIsNormalizedNotZeroed) {
  const std::string path = write("traj.txt", "0.05 0 0 1 0 2.2e206 0 1\n");
  TrajectoryReadReport report;
  const StampedTrajectory traj = readTumTrajectory(path, &report);
  ASSERT_EQ(traj.size(), 1u);
  EXPECT_DOUBLE_EQ(traj[0].q_w_c.y(), 1.0);
  EXPECT_NEAR(traj[0].q_w_c.norm(), 1.0, 1e-12);
  EXPECT_EQ(report.normalized_quaternions, 1u);
  expectTumError("0 0 0 0 1.5e308 1.5e308 1.5e308 1.5e308\n", 1, "quaternion too large to normalize");
}

TEST_F(TrajectoryIo, MissingAndEmptyFiles) {
  EXPECT_THROW(readTumTrajectory((dir_ / "does_not_exist.txt").string()), InputError);
  try {
    readTumTrajectory(write("empty.txt", ""));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("no poses"), std::string::npos);
  }
  EXPECT_THROW(readTumTrajectory(write("comments.txt", "# only a header\n\n")), InputError);
  EXPECT_THROW(readVelocities(write("empty_vel.txt", "")), InputError);
}

TEST_F(TrajectoryIo, MalformedLinesNameTheLine) {
  expectTumError("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n", 2, "expected 8 fields");
  expectTumError("0 0 0 0 0 0 0 1 5\n", 1, "found 9");
  expectTumError("0 0 0 0 0 0 0 1\n# c\n1 0 x 0 0 0 0 1\n", 3, "field 3 'x' is not a number");
  expectTumError("0 0 0 nan 0 0 0 1\n", 1, "field 4");
  expectTumError("0 0 0 0 0 0 0 inf\n", 1, "field 8");
  expectTumError("abc 0 0 0 0 0 0 1\n", 1, "time 'abc'");
  expectTumError("nan 0 0 0 0 0 0 1\n", 1, "time 'nan'");
  expectTumError("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 0\n", 2, "zero quaternion");
  expectTumError("0 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n1.5 0 0 0 0 0 0 1\n", 3, "earlier than the previous");
}

TEST_F(TrajectoryIo, EqualTimesAreAccepted) {
  const StampedTrajectory traj = readTumTrajectory(write("t.txt", "1 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n"));
  ASSERT_EQ(traj.size(), 2u);
  EXPECT_EQ(traj[0].t_ns, traj[1].t_ns);
}

TEST_F(TrajectoryIo, UnwritablePathThrows) {
  EXPECT_THROW(writeTumTrajectory((dir_ / "no_such_dir" / "x.txt").string(), {}), Error);
}

}  // namespace
}  // namespace asynevo
