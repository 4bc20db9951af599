#pragma once
// A dataset on disk: an ECD-style folder (events.txt, calib.txt, optional groundtruth.txt) or a single
// event file. Resolving a path tells which files play which role; nothing is read yet.

#include <optional>
#include <string>
#include <utility>

namespace asynevo {

struct DatasetFiles {
  std::string root;                        ///< the folder (or the file's folder)
  std::string events;                      ///< event file
  std::optional<std::string> calibration;  ///< calib.txt or a Kalibr camchain YAML, when present
  std::optional<std::string> groundtruth;  ///< groundtruth.txt (ECD/TUM) or MVSEC *_gt.hdf5
};

/// Resolves `path`: a folder must hold an event file (events.txt, events.aevt or *_data.hdf5); a file
/// is taken as the event file. Throws InputError when nothing usable is found.
DatasetFiles resolveDataset(const std::string& path);

/// True for calibration files in Kalibr camchain YAML form (by extension: .yaml / .yml).
bool isKalibrCalibration(const std::string& path);

/// The sensor size to read a dataset's events with: the resolution of its Kalibr calibration when it has
/// one, else {0, 0} (the event format's own default: 240×180 for ECD text, 346×260 for MVSEC, the
/// header for .aevt). An explicit configuration (Config::sensor) overrides this in the commands.
std::pair<int, int> sensorSizeFromCalibration(const DatasetFiles& files);

}  // namespace asynevo
