#include "asynevo/io/calibration_io.hpp"

#include <gtest/gtest.h>

#include <string>

#include "asynevo/core/error.hpp"
#include "io_test_util.hpp"

namespace asynevo {
namespace {

using testing::TempDir;

/// Runs `read` and returns the InputError's what(); fails the test when nothing is thrown.
template <class F>
std::string inputErrorOf(F&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

TEST(EcdCalibration, ReadsTheBundledDavis240cFile) {
  const CameraModel camera = readEcdCalibration(testing::dataPath("ecd/shapes_rotation/calib.txt"));
  EXPECT_EQ(camera.width(), 240);
  EXPECT_EQ(camera.height(), 180);
  EXPECT_DOUBLE_EQ(camera.fx(), 199.092366542);
  EXPECT_DOUBLE_EQ(camera.fy(), 198.82882047);
  EXPECT_DOUBLE_EQ(camera.cx(), 132.192071378);
  EXPECT_DOUBLE_EQ(camera.cy(), 110.712660011);
  EXPECT_EQ(camera.distortionModel(), DistortionModel::kRadtan);
  ASSERT_EQ(camera.coefficients().size(), 5u);
  EXPECT_DOUBLE_EQ(camera.coefficients()[0], -0.368436311798);
  EXPECT_DOUBLE_EQ(camera.coefficients()[1], 0.150947243557);
  EXPECT_DOUBLE_EQ(camera.coefficients()[2], -0.000296130534385);
  EXPECT_DOUBLE_EQ(camera.coefficients()[3], -0.000759431726241);
  EXPECT_DOUBLE_EQ(camera.coefficients()[4], 0.0);
  // Same as the built-in ECD model.
  const CameraModel builtin = CameraModel::davis240cEcd();
  EXPECT_EQ(camera.coefficients(), builtin.coefficients());
  EXPECT_EQ(camera.fx(), builtin.fx());
}

TEST(EcdCalibration, SizeIsPassedIn) {
  const CameraModel camera = readEcdCalibration(testing::dataPath("ecd/shapes_rotation/calib.txt"), 346, 260);
  EXPECT_EQ(camera.width(), 346);
  EXPECT_EQ(camera.height(), 260);
}

TEST(EcdCalibration, SkipsCommentsAndBlankLines) {
  TempDir dir;
  const std::string path = dir.write("calib.txt", "# DAVIS\n\n200 201 120 90 0.1 0.01 0 0 0\r\n\n");
  const CameraModel camera = readEcdCalibration(path);
  EXPECT_EQ(camera.fy(), 201);
  EXPECT_EQ(camera.coefficients()[1], 0.01);
}

TEST(EcdCalibration, WriteReadRoundTripIsExact) {
  TempDir dir;
  const CameraModel camera = CameraModel::davis240cEcd();
  writeEcdCalibration(dir.file("calib.txt"), camera);
  const CameraModel back = readEcdCalibration(dir.file("calib.txt"));
  EXPECT_EQ(back.fx(), camera.fx());
  EXPECT_EQ(back.cy(), camera.cy());
  EXPECT_EQ(back.coefficients(), camera.coefficients());
  const CameraModel fisheye(346, 260, 180, 180, 170, 130, DistortionModel::kEquidistant,
                            {0.1, 0.01, 0.001, 0.0});
  EXPECT_THROW(writeEcdCalibration(dir.file("fisheye.txt"), fisheye), Error);
}

TEST(EcdCalibration, BadInputNamesFileAndLine) {
  TempDir dir;
  const std::string missing = dir.file("missing.txt");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(missing); }), missing + ": cannot open file");

  const std::string empty = dir.write("empty.txt", "\n# nothing\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(empty); }),
            empty + ": empty file: expected one line fx fy cx cy k1 k2 p1 p2 k3");

  const std::string short_line = dir.write("short.txt", "# c\n199 198 132 110 -0.3 0.1 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(short_line); }),
            short_line + ":2: expected 9 fields (fx fy cx cy k1 k2 p1 p2 k3), found 8");

  const std::string long_line = dir.write("long.txt", "199 198 132 110 -0.3 0.1 0 0 0 7\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(long_line); }),
            long_line + ":1: expected 9 fields (fx fy cx cy k1 k2 p1 p2 k3), found 10");

  const std::string text = dir.write("text.txt", "199 198 abc 110 -0.3 0.1 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(text); }), text + ":1: field 3 'abc' is not a number");

  const std::string comma = dir.write("comma.txt", "199,5 198 132 110 -0.3 0.1 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(comma); }), comma + ":1: field 1 '199,5' is not a number");

  const std::string nan = dir.write("nan.txt", "199 198 132 110 nan 0.1 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(nan); }), nan + ":1: field 5 'nan' is not finite");

  const std::string inf = dir.write("inf.txt", "199 -inf 132 110 0 0.1 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(inf); }), inf + ":1: field 2 '-inf' is not finite");

  const std::string two = dir.write("two.txt", "199 198 132 110 0 0 0 0 0\n199 198 132 110 0 0 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(two); }),
            two + ":2: expected a single line (fx fy cx cy k1 k2 p1 p2 k3), found a second one");

  const std::string negative = dir.write("negative.txt", "\n-199 198 132 110 0 0 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(negative); }),
            negative + ":2: focal lengths must be positive, got fx=-199 fy=198");

  const std::string ok = dir.write("ok.txt", "199 198 132 110 0 0 0 0 0\n");
  EXPECT_EQ(inputErrorOf([&] { readEcdCalibration(ok, 0, 180); }),
            ok + ":1: camera size must be positive, got 0x180");
}

constexpr const char* kKalibrRadtan = R"(cam0:
  cam_overlaps: []
  camera_model: pinhole
  distortion_coeffs: [-0.3686, 0.1509, -0.0003, -0.0008]
  distortion_model: radtan
  intrinsics: [199.09, 198.83, 132.19, 110.71]
  resolution: [240, 180]
  rostopic: /dvs/events
)";

TEST(KalibrCalibration, ReadsRadtanCamchain) {
  TempDir dir;
  const CameraModel camera = readKalibrCalibration(dir.write("camchain.yaml", kKalibrRadtan));
  EXPECT_EQ(camera.width(), 240);
  EXPECT_EQ(camera.height(), 180);
  EXPECT_EQ(camera.fx(), 199.09);
  EXPECT_EQ(camera.fy(), 198.83);
  EXPECT_EQ(camera.cx(), 132.19);
  EXPECT_EQ(camera.cy(), 110.71);
  EXPECT_EQ(camera.distortionModel(), DistortionModel::kRadtan);
  EXPECT_EQ(camera.coefficients(), (std::vector<double>{-0.3686, 0.1509, -0.0003, -0.0008, 0.0}));
}

TEST(KalibrCalibration, ReadsEquidistantOfTheNamedCamera) {
  TempDir dir;
  const std::string path = dir.write("camchain.yaml", std::string(kKalibrRadtan) + R"(cam1:
  camera_model: pinhole
  distortion_coeffs: [-0.0395, 0.0132, -0.0124, 0.0031]
  distortion_model: equidistant
  intrinsics: [180.5, 180.1, 171.3, 128.9]
  resolution: [346, 260]
)");
  const CameraModel camera = readKalibrCalibration(path, "cam1");
  EXPECT_EQ(camera.width(), 346);
  EXPECT_EQ(camera.height(), 260);
  EXPECT_EQ(camera.distortionModel(), DistortionModel::kEquidistant);
  EXPECT_EQ(camera.coefficients(), (std::vector<double>{-0.0395, 0.0132, -0.0124, 0.0031}));
  EXPECT_EQ(camera.cx(), 171.3);
  // readCalibration picks the format from the extension.
  EXPECT_EQ(readCalibration(path).distortionModel(), DistortionModel::kRadtan);
}

TEST(KalibrCalibration, WriteReadRoundTripIsExact) {
  TempDir dir;
  for (const CameraModel& camera :
       {CameraModel::davis240cEcd(),
        CameraModel(346, 260, 180.5, 180.1, 171.3, 128.9, DistortionModel::kEquidistant,
                    {-0.0395, 0.0132, -0.0124, 0.0031}),
        CameraModel::pinhole(640, 480, 500, 501, 319.5, 239.5)}) {
    writeKalibrCalibration(dir.file("cam.yaml"), camera);
    const CameraModel back = readKalibrCalibration(dir.file("cam.yaml"));
    EXPECT_EQ(back.summary(), camera.summary());
    EXPECT_EQ(back.coefficients(), camera.coefficients());
    EXPECT_EQ(back.fx(), camera.fx());
    EXPECT_EQ(back.width(), camera.width());
  }
}

std::string kalibrWith(const std::string& distortion_model, const std::string& coeffs,
                       const std::string& intrinsics = "[199.0, 198.0, 132.0, 110.0]",
                       const std::string& resolution = "[240, 180]",
                       const std::string& camera_model = "pinhole") {
  return "cam0:\n  camera_model: " + camera_model + "\n  distortion_model: " + distortion_model +
         "\n  distortion_coeffs: " + coeffs + "\n  intrinsics: " + intrinsics +
         "\n  resolution: " + resolution + "\n";
}

TEST(KalibrCalibration, BadInputNamesFileAndLine) {
  TempDir dir;
  const std::string missing = dir.file("missing.yaml");
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(missing); }), missing + ": cannot open file");

  const std::string empty = dir.write("empty.yaml", "");
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(empty); }),
            empty + ": empty file: expected a Kalibr camchain with cam0");

  const std::string no_cam = dir.write("nocam.yaml", "cam1:\n  camera_model: pinhole\n");
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(no_cam); }),
            no_cam + ":1: no camera 'cam0' in the file");

  // DSEC's cam_to_cam.yaml is not a camchain: the message says what to give instead.
  const std::string dsec = dir.write("cam_to_cam.yaml",
                                     "intrinsics:\n  cam0:\n    camera_matrix: [555.6, 555.8, 342.5, 215.2]\n"
                                     "  camRect0:\n    camera_matrix: [569.7, 569.7, 335.0, 221.2]\n"
                                     "    resolution: [640, 480]\nextrinsics:\n  R_rect0: [[1, 0, 0], [0, 1, 0], "
                                     "[0, 0, 1]]\n");
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(dsec); }),
            dsec + ":1: this is DSEC's cam_to_cam.yaml, which AsynEVO does not read: for rectified events "
                   "(rectify_map.h5) write camRect0's camera_matrix [fx, fy, cx, cy] (camRect3 for the right camera) "
                   "as a calib.txt 'fx fy cx cy 0 0 0 0 0' (docs/reference/formats.md#rectification)");

  const std::string omni =
      dir.write("omni.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[1, 2, 3, 4]", "[240, 180]", "omni"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(omni); }),
            omni + ":2: unsupported camera_model 'omni' (supported: pinhole)");

  const std::string fov = dir.write("fov.yaml", kalibrWith("fov", "[0.9]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(fov); }),
            fov + ":3: unsupported distortion_model 'fov' (supported: radtan, equidistant, none)");

  const std::string count = dir.write("count.yaml", kalibrWith("equidistant", "[0.1, 0.2, 0.3]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(count); }),
            count + ":4: 'distortion_coeffs' needs 4 values, found 3");

  const std::string radtan6 =
      dir.write("radtan6.yaml", kalibrWith("radtan", "[0.1, 0.2, 0.3, 0.4, 0.5, 0.6]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(radtan6); }),
            radtan6 + ":4: 'distortion_coeffs' needs 4 or 5 values, found 6");

  const std::string intr =
      dir.write("intr.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[199.0, 198.0, 132.0]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(intr); }),
            intr + ":5: 'intrinsics' needs 4 values, found 3");

  const std::string text =
      dir.write("text.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[199.0, fx, 132.0, 1]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(text); }),
            text + ":5: intrinsics[1] 'fx' is not a number");

  const std::string nan = dir.write("nan.yaml", kalibrWith("radtan", "[0, .nan, 0, 0]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(nan); }),
            nan + ":4: distortion_coeffs[1] '.nan' is not finite");

  const std::string nan2 = dir.write("nan2.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[nan, 1, 2, 3]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(nan2); }),
            nan2 + ":5: intrinsics[0] 'nan' is not finite");

  const std::string res =
      dir.write("res.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[199, 198, 132, 110]", "[240.5, 180]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(res); }),
            res + ":6: resolution must be two positive integers, found 240.5");

  const std::string no_intr =
      dir.write("nointr.yaml", "cam0:\n  camera_model: pinhole\n  distortion_model: none\n");
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(no_intr); }), no_intr + ":2: missing key 'intrinsics'");

  const std::string focal =
      dir.write("focal.yaml", kalibrWith("radtan", "[0, 0, 0, 0]", "[0, 198, 132, 110]"));
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(focal); }),
            focal + ":5: focal lengths must be positive, got fx=0 fy=198");

  const std::string broken = dir.write("broken.yaml", "cam0:\n  intrinsics: [1, 2\n  resolution: [3, 4]\n");
  // yaml-cpp's own message (Debian 12, yaml-cpp 0.7), at the line where the parser noticed.
  EXPECT_EQ(inputErrorOf([&] { readKalibrCalibration(broken); }),
            broken + ":3: end of sequence flow not found");
}

}  // namespace
}  // namespace asynevo
