#include "asynevo/eval/alignment.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace asynevo::eval {
namespace {

Eigen::Matrix3Xd points() {
  Eigen::Matrix3Xd p(3, 6);
  p << 0, 1, 2, 0.5, -1, 3,  //
      0, 0, 1, 2, -0.5, 1,   //
      0, 0.2, -0.3, 1, 0.7, -1;
  return p;
}

TEST(Umeyama, RecoversAKnownSimilarity) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -4, 2);
  const Eigen::Matrix3Xd data = points();
  const Eigen::Matrix3Xd model = ((2.5 * R * data).colwise() + t).eval();
  const Similarity sim = umeyama(model, data, /*with_scale=*/true);
  EXPECT_NEAR(sim.scale, 2.5, 1e-12);
  EXPECT_TRUE(sim.rotation.isApprox(R, 1e-12));
  EXPECT_TRUE(sim.translation.isApprox(t, 1e-12));

  const Eigen::Matrix3Xd model_rigid = ((R * data).colwise() + t).eval();
  const Similarity rigid = umeyama(model_rigid, data, /*with_scale=*/false);
  EXPECT_EQ(rigid.scale, 1.0);
  EXPECT_TRUE(rigid.rotation.isApprox(R, 1e-12));
  EXPECT_TRUE(rigid.translation.isApprox(t, 1e-12));
}

TEST(Umeyama, YawOnlyRecoversARotationAboutZ) {
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t(1, 2, 3);
  const Eigen::Matrix3Xd data = points();
  const Eigen::Matrix3Xd model = ((Rz * data).colwise() + t).eval();
  const Similarity sim = umeyama(model, data, false, /*yaw_only=*/true);
  EXPECT_TRUE(sim.rotation.isApprox(Rz, 1e-12));
  EXPECT_TRUE(sim.translation.isApprox(t, 1e-12));
}

TEST(Umeyama, NoReflectionForMirroredData) {
  Eigen::Matrix3Xd data = points();
  Eigen::Matrix3Xd model = data;
  model.row(2) *= -1.0;  // a mirror image: the best proper rotation is not a reflection
  const Similarity sim = umeyama(model, data, true);
  EXPECT_NEAR(sim.rotation.determinant(), 1.0, 1e-12);
}

TEST(AlignTrajectory, SingleFrameVariantsUseTheFirstPose) {
  const Eigen::Matrix3d R_align = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t_align(1, -1, 0.5);
  std::vector<Eigen::Vector3d> p_est = {{1, 2, 3}, {2, 2, 2}}, p_gt;
  std::vector<Eigen::Matrix3d> R_est = {Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized())
                                            .toRotationMatrix(),
                                        Eigen::Matrix3d::Identity()},
                               R_gt;
  for (std::size_t i = 0; i < 2; ++i) {
    p_gt.push_back(R_align * p_est[i] + t_align);
    R_gt.push_back(R_align * R_est[i]);
  }
  for (AlignType type : {AlignType::kSe3, AlignType::kPosYaw}) {
    const Similarity sim = alignTrajectory(p_est, R_est, p_gt, R_gt, type, 1);
    EXPECT_TRUE(sim.rotation.isApprox(R_align, 1e-12)) << alignTypeName(type);
    EXPECT_TRUE(sim.translation.isApprox(t_align, 1e-12)) << alignTypeName(type);
  }
  const Similarity none = alignTrajectory(p_est, R_est, p_gt, R_gt, AlignType::kNone);
  EXPECT_TRUE(none.rotation.isIdentity());
  EXPECT_EQ(none.scale, 1.0);
}

TEST(AlignTrajectory, RejectsBadFrameCounts) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Eigen::Matrix3d> R(3, Eigen::Matrix3d::Identity());
  EXPECT_THROW(alignTrajectory(p, R, p, R, AlignType::kSim3, 1), EvalError);
  EXPECT_THROW(alignTrajectory(p, R, p, R, AlignType::kSim3, 4), EvalError);
  EXPECT_THROW(alignTrajectory(p, R, p, R, AlignType::kSe3, 0), EvalError);
  EXPECT_THROW(alignTrajectory(p, R, p, R, AlignType::kSe3, -2), EvalError);
  EXPECT_NO_THROW(alignTrajectory(p, R, p, R, AlignType::kSim3, 2));
}

TEST(AlignType, ParsesRpgNames) {
  EXPECT_EQ(parseAlignType("sim3"), AlignType::kSim3);
  EXPECT_EQ(parseAlignType("se3"), AlignType::kSe3);
  EXPECT_EQ(parseAlignType("posyaw"), AlignType::kPosYaw);
  EXPECT_EQ(parseAlignType("none"), AlignType::kNone);
  EXPECT_FALSE(parseAlignType("SIM3").has_value());
  EXPECT_STREQ(alignTypeName(AlignType::kPosYaw), "posyaw");
}

}  // namespace
}  // namespace asynevo::eval
