#pragma once
// A dataset on disk: an ECD-style folder (events.txt, calib.txt, optional groundtruth.txt) or a single
// event file. Resolving a path tells which files play which role; nothing is read yet.

#include <optional>
#include <string>

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

}  // namespace asynevo
