#pragma once
// Camera calibration files (docs/camera_models.md):
//
//   ECD calib.txt          one line "fx fy cx cy k1 k2 p1 p2 k3" (pinhole + radtan). The file has no
//                          resolution: width and height are passed in (DAVIS240C 240x180 by default).
//   Kalibr camchain YAML   cam0: {camera_model: pinhole, distortion_model: radtan|equidistant|none,
//                          intrinsics: [fx, fy, cx, cy], distortion_coeffs: [...], resolution: [w, h]}
//
// Every problem (missing file, wrong field count, non-numeric or non-finite value, unsupported model,
// invalid intrinsics) throws InputError naming the file and, where there is one, the line.

#include <string>

#include "asynevo/core/camera/camera_model.hpp"

namespace asynevo {

/// Reads an ECD calib.txt. Blank lines and '#' comment lines are skipped; exactly one record of 9
/// numbers must remain.
CameraModel readEcdCalibration(const std::string& path, int width = 240, int height = 180);

/// Reads camera `camera` (default "cam0") of a Kalibr camchain YAML file. Radtan accepts 4
/// (k1 k2 p1 p2, Kalibr's own layout) or 5 (… k3) coefficients; equidistant takes 4 (k1..k4).
CameraModel readKalibrCalibration(const std::string& path, const std::string& camera = "cam0");

/// Reads either format: files ending in .yaml/.yml are Kalibr, anything else ECD calib.txt (which then
/// takes width/height).
CameraModel readCalibration(const std::string& path, int width = 240, int height = 180);

/// Writes an ECD calib.txt (9 values, full double precision). Only radtan and undistorted pinhole
/// cameras fit the format; other models throw Error. Throws Error when the file cannot be written.
void writeEcdCalibration(const std::string& path, const CameraModel& camera);

/// Writes a Kalibr camchain YAML with one camera, cam0, that readKalibrCalibration reads back exactly.
void writeKalibrCalibration(const std::string& path, const CameraModel& camera);

}  // namespace asynevo
