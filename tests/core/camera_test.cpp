#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"

namespace asynevo {
namespace {

// A Kalibr-style equidistant calibration of a DAVIS346-sized fisheye (values of the usual magnitude).
CameraModel equidistantCamera() {
  return CameraModel(346, 260, 180.5, 180.1, 171.3, 128.9, DistortionModel::kEquidistant,
                     {-0.0395, 0.0132, -0.0124, 0.0031});
}

// A strong fisheye (k1 > 0) whose corners are ~80 degrees off axis (normalized radius up to ~6).
CameraModel strongEquidistantCamera() {
  return CameraModel(640, 480, 270.0, 270.0, 320.0, 240.0, DistortionModel::kEquidistant,
                     {0.05, -0.01, 0.002, -0.0002});
}

std::vector<CameraModel> allCameras() {
  return {CameraModel::davis240cEcd(), equidistantCamera(), strongEquidistantCamera(),
          CameraModel::pinhole(240, 180, 200, 200, 120, 90)};
}

// Round trip over every pixel centre and a sub-pixel offset: unproject, put the point at a depth,
// project back.
TEST(CameraModel, ProjectUnprojectRoundTripOverWholeImage) {
  for (const CameraModel& camera : allCameras()) {
    double worst = 0;
    for (int y = 0; y < camera.height(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        for (double offset : {0.0, 0.37}) {
          const Eigen::Vector2d pixel(x + offset, y - offset);
          const auto xn = camera.unproject(pixel);
          ASSERT_TRUE(xn.has_value()) << camera.summary() << " pixel " << pixel.transpose();
          const Eigen::Vector3d p_c = 2.5 * Eigen::Vector3d(xn->x(), xn->y(), 1.0);
          const auto back = camera.project(p_c);
          ASSERT_TRUE(back.has_value());
          worst = std::max(worst, (*back - pixel).norm());
        }
      }
    }
    EXPECT_LT(worst, 1e-9) << camera.summary();
    std::printf("[ figure ] round trip %s: worst %.3g px\n", distortionModelName(camera.distortionModel()),
                worst);
  }
}

TEST(CameraModel, BearingIsUnitAndProjectsBack) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const Eigen::Vector2d pixel(3.25, 171.5);
  const auto bearing = camera.unprojectBearing(pixel);
  ASSERT_TRUE(bearing.has_value());
  EXPECT_NEAR(bearing->norm(), 1.0, 1e-15);
  EXPECT_NEAR((*camera.project(*bearing) - pixel).norm(), 0.0, 1e-9);
}

TEST(CameraModel, ProjectRejectsPointsBehindTheCamera) {
  const CameraModel camera = CameraModel::davis240cEcd();
  EXPECT_FALSE(camera.project(Eigen::Vector3d(0.1, 0.2, -1.0)).has_value());
  EXPECT_FALSE(camera.project(Eigen::Vector3d(0.1, 0.2, 0.0)).has_value());
  const auto centre = camera.project(Eigen::Vector3d(0, 0, 3));
  ASSERT_TRUE(centre.has_value());
  EXPECT_DOUBLE_EQ(centre->x(), camera.cx());
  EXPECT_DOUBLE_EQ(centre->y(), camera.cy());
}

TEST(CameraModel, DistortJacobianMatchesFiniteDifferences) {
  for (const CameraModel& camera : allCameras()) {
    for (const Eigen::Vector2d& xn :
         {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-0.7, 0.5), Eigen::Vector2d(1e-3, 0)}) {
      const Eigen::Matrix2d J = camera.distortJacobian(xn);
      const double h = 1e-6;
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d e = Eigen::Vector2d::Unit(k) * h;
        const Eigen::Vector2d numeric = (camera.distort(xn + e) - camera.distort(xn - e)) / (2 * h);
        EXPECT_NEAR((J.col(k) - numeric).norm(), 0.0, 1e-8) << camera.summary() << " at " << xn.transpose();
      }
    }
  }
}

TEST(CameraModel, ProjectionJacobianMatchesFiniteDifferences) {
  for (const CameraModel& camera : allCameras()) {
    const Eigen::Vector3d p(0.4, -0.3, 1.7);
    Eigen::Matrix<double, 2, 3> J;
    const auto pixel = camera.project(p, &J);
    ASSERT_TRUE(pixel.has_value());
    EXPECT_EQ(*pixel, *camera.project(p));
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(k) * h;
      const Eigen::Vector2d numeric = (*camera.project(p + e) - *camera.project(p - e)) / (2 * h);
      EXPECT_NEAR((J.col(k) - numeric).norm(), 0.0, 1e-5 * (1 + numeric.norm())) << camera.summary();
    }
  }
  Eigen::Matrix<double, 2, 3> J;
  EXPECT_FALSE(CameraModel::davis240cEcd().project(Eigen::Vector3d(0, 0, -1), &J).has_value());
}

// Our undistortion against OpenCV's, in pixels (P = K), over a grid covering the whole image. OpenCV is
// given enough iterations and a tight tolerance (its default is 5 iterations for radtan, which is not
// converged at the corners of the strongly distorted ECD calibration).
TEST(CameraModel, RadtanAgreesWithOpenCvUndistortPoints) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
  const std::vector<double>& c = camera.coefficients();
  const cv::Mat D = (cv::Mat_<double>(1, 5) << c[0], c[1], c[2], c[3], c[4]);
  std::vector<cv::Point2d> src;
  for (double y = -0.5; y <= camera.height() - 0.5; y += 2.25) {
    for (double x = -0.5; x <= camera.width() - 0.5; x += 2.25) src.emplace_back(x, y);
  }
  std::vector<cv::Point2d> dst;
  cv::undistortPoints(src, dst, K, D, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 1000, 1e-14));
  ASSERT_EQ(dst.size(), src.size());
  double worst = 0;
  for (std::size_t i = 0; i < src.size(); ++i) {
    const auto xn = camera.unproject(Eigen::Vector2d(src[i].x, src[i].y));
    ASSERT_TRUE(xn.has_value());
    const Eigen::Vector2d ours(camera.fx() * xn->x() + camera.cx(), camera.fy() * xn->y() + camera.cy());
    worst = std::max(worst, (ours - Eigen::Vector2d(dst[i].x, dst[i].y)).norm());
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ figure ] radtan vs cv::undistortPoints: %zu points, worst %.3g px\n", src.size(), worst);
}

TEST(CameraModel, EquidistantAgreesWithOpenCvFisheyeUndistortPoints) {
  for (const CameraModel& camera : {equidistantCamera(), strongEquidistantCamera()}) {
    const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
    const std::vector<double>& c = camera.coefficients();
    const cv::Vec4d D(c[0], c[1], c[2], c[3]);
    std::vector<cv::Point2d> src;
    for (double y = -0.5; y <= camera.height() - 0.5; y += 2.5) {
      for (double x = -0.5; x <= camera.width() - 0.5; x += 2.5) src.emplace_back(x, y);
    }
    std::vector<cv::Point2d> dst;
    cv::fisheye::undistortPoints(
        src, dst, K, D, cv::noArray(), K,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-15));
    ASSERT_EQ(dst.size(), src.size());
    double worst = 0;
    for (std::size_t i = 0; i < src.size(); ++i) {
      const auto xn = camera.unproject(Eigen::Vector2d(src[i].x, src[i].y));
      ASSERT_TRUE(xn.has_value());
      const Eigen::Vector2d ours(camera.fx() * xn->x() + camera.cx(), camera.fy() * xn->y() + camera.cy());
      worst = std::max(worst, (ours - Eigen::Vector2d(dst[i].x, dst[i].y)).norm());
    }
    EXPECT_LT(worst, 1e-6) << camera.summary();
    std::printf("[ figure ] equidistant vs cv::fisheye::undistortPoints (%s): %zu points, worst %.3g px\n",
                camera.summary().c_str(), src.size(), worst);
  }
}

// Our distortion against OpenCV's projectPoints / fisheye::projectPoints (the forward model).
TEST(CameraModel, ProjectionAgreesWithOpenCv) {
  std::vector<cv::Point3d> points;
  for (double y = -0.6; y <= 0.6; y += 0.1) {
    for (double x = -0.8; x <= 0.8; x += 0.1) points.emplace_back(x * 2, y * 2, 2.0);
  }
  const cv::Vec3d rvec(0, 0, 0), tvec(0, 0, 0);
  {
    const CameraModel camera = CameraModel::davis240cEcd();
    const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
    const std::vector<double>& c = camera.coefficients();
    std::vector<cv::Point2d> cv_pixels;
    cv::projectPoints(points, rvec, tvec, K, c, cv_pixels);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto ours = camera.project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
      ASSERT_TRUE(ours.has_value());
      EXPECT_NEAR(ours->x(), cv_pixels[i].x, 1e-9);
      EXPECT_NEAR(ours->y(), cv_pixels[i].y, 1e-9);
    }
  }
  {
    const CameraModel camera = strongEquidistantCamera();
    const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
    const std::vector<double>& c = camera.coefficients();
    std::vector<cv::Point2d> cv_pixels;
    cv::fisheye::projectPoints(points, cv_pixels, rvec, tvec, K, cv::Vec4d(c[0], c[1], c[2], c[3]));
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto ours = camera.project(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
      ASSERT_TRUE(ours.has_value());
      EXPECT_NEAR(ours->x(), cv_pixels[i].x, 1e-9);
      EXPECT_NEAR(ours->y(), cv_pixels[i].y, 1e-9);
    }
  }
}

template <typename Scalar>
void expectTableMatchesPerPixelUndistortion(const CameraModel& camera, double tolerance) {
  const UndistortionTable<Scalar> table = camera.undistortionTable<Scalar>();
  ASSERT_EQ(table.width(), camera.width());
  ASSERT_EQ(table.height(), camera.height());
  EXPECT_EQ(table.invalidCount(), 0u);
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      const auto xn = camera.unproject(Eigen::Vector2d(x, y));
      ASSERT_TRUE(xn.has_value());
      ASSERT_TRUE(table.valid(x, y));
      ASSERT_NEAR(table.xn(x, y), xn->x(), tolerance) << x << "," << y;
      ASSERT_NEAR(table.yn(x, y), xn->y(), tolerance) << x << "," << y;
      ASSERT_EQ(table.at(x, y).x(), table.xn(x, y));
    }
  }
}

TEST(UndistortionTable, EqualsPerPixelUndistortion) {
  for (const CameraModel& camera : allCameras()) {
    expectTableMatchesPerPixelUndistortion<double>(camera, 0.0);
    // float: the nearest float to the double value (relative 2^-24 of |xn| <= ~2).
    expectTableMatchesPerPixelUndistortion<float>(camera, 2.5e-7);
  }
}

// A radtan calibration with a fold inside the image: beyond r where d r_d / d r = 0 the inverse has
// no solution on the principal branch. The undistortion must say so, and the table must mark it.
TEST(CameraModel, ReportsNonConvergenceInsteadOfGarbage) {
  const CameraModel camera(240, 180, 100, 100, 120, 90, DistortionModel::kRadtan, {-0.9, 0.0, 0.0, 0.0, 0.0});
  // r_d(r) = r - 0.9 r³ peaks at r = 1/sqrt(2.7) = 0.609, r_d = 0.406; a distorted radius of 1.1 has no
  // inverse on the principal branch.
  const UndistortResult bad = camera.undistort(Eigen::Vector2d(1.1, 0.0));
  EXPECT_FALSE(bad.converged);
  EXPECT_FALSE(camera.unproject(Eigen::Vector2d(120 + 110, 90)).has_value());
  const UndistortResult good = camera.undistort(Eigen::Vector2d(0.3, 0.1));
  EXPECT_TRUE(good.converged);
  EXPECT_LT((camera.distort(good.xn) - Eigen::Vector2d(0.3, 0.1)).norm(), 1e-12);
  const auto table = camera.undistortionTable<float>();
  EXPECT_GT(table.invalidCount(), 0u);
  EXPECT_FALSE(table.valid(0, 0));
  EXPECT_TRUE(table.valid(120, 90));
  EXPECT_FALSE(camera.undistort(Eigen::Vector2d(std::nan(""), 0.0)).converged);
}

// Equidistant: theta_d(pi/2) bounds the distorted radius of any point in front of the camera; a pixel
// beyond it has no normalized coordinates (its ray would be 90 degrees or more off axis).
TEST(CameraModel, EquidistantReportsRaysBeyondNinetyDegrees) {
  const CameraModel camera(640, 480, 230.0, 230.0, 320.0, 240.0, DistortionModel::kEquidistant,
                           {0.05, -0.01, 0.002, -0.0002});
  // theta_d(pi/2) = 1.704 < |xd| = |(-320, -240)| / 230 = 1.739 at the corner pixel (0, 0).
  EXPECT_FALSE(camera.undistort(camera.pixelToDistorted(Eigen::Vector2d(0, 0))).converged);
  EXPECT_FALSE(camera.unproject(Eigen::Vector2d(0, 0)).has_value());
  EXPECT_TRUE(camera.unproject(Eigen::Vector2d(320, 240)).has_value());
  const auto table = camera.undistortionTable<double>();
  EXPECT_FALSE(table.valid(0, 0));
  EXPECT_TRUE(table.valid(320, 240));
}

TEST(CameraModel, RejectsInvalidParameters) {
  EXPECT_THROW(CameraModel(0, 180, 200, 200, 120, 90), std::invalid_argument);
  EXPECT_THROW(CameraModel(240, 180, -1, 200, 120, 90), std::invalid_argument);
  EXPECT_THROW(CameraModel(240, 180, std::nan(""), 200, 120, 90), std::invalid_argument);
  EXPECT_THROW(CameraModel(240, 180, 200, 200, 120, 90, DistortionModel::kEquidistant, {0.1, 0.2}),
               std::invalid_argument);
  EXPECT_THROW(CameraModel(240, 180, 200, 200, 120, 90, DistortionModel::kNone, {0.1}),
               std::invalid_argument);
  // radtan with four coefficients means k3 = 0.
  const CameraModel four(240, 180, 200, 200, 120, 90, DistortionModel::kRadtan, {0.1, 0.2, 0.3, 0.4});
  ASSERT_EQ(four.coefficients().size(), 5u);
  EXPECT_EQ(four.coefficients()[4], 0.0);
}

TEST(CameraModel, SummaryNamesTheModel) {
  EXPECT_EQ(CameraModel::pinhole(240, 180, 200, 201, 120, 90).summary(),
            "240x180 fx=200 fy=201 cx=120 cy=90 none");
  EXPECT_NE(CameraModel::davis240cEcd().summary().find("radtan [-0.368436"), std::string::npos);
}

}  // namespace
}  // namespace asynevo
