#include "asynevo/io/dataset.hpp"

#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"

namespace asynevo {

namespace fs = std::filesystem;

namespace {

std::optional<std::string> firstExisting(const fs::path& dir, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    if (fs::is_regular_file(dir / name)) return (dir / name).string();
  }
  return std::nullopt;
}

// MVSEC names its files <sequence>_data.hdf5 and <sequence>_gt.hdf5.
std::optional<std::string> findBySuffix(const fs::path& dir, const std::string& suffix) {
  std::optional<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      if (!found || entry.path().string() < *found) found = entry.path().string();  // deterministic choice
    }
  }
  return found;
}

}  // namespace

DatasetFiles resolveDataset(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw InputError(path, "no such file or folder");
  DatasetFiles files;
  if (fs::is_directory(p, ec)) {
    files.root = p.string();
    if (auto events = firstExisting(p, {"events.aevt", "events.txt"})) {
      files.events = *events;
    } else if (auto hdf5 = findBySuffix(p, "_data.hdf5")) {
      files.events = *hdf5;
    } else {
      throw InputError(path, "no event file in this folder (expected events.txt, events.aevt or *_data.hdf5)");
    }
  } else {
    files.events = p.string();
    files.root = p.parent_path().empty() ? "." : p.parent_path().string();
  }
  const fs::path root(files.root);
  files.calibration = firstExisting(root, {"calib.txt", "camchain.yaml", "calib.yaml"});
  if (!files.calibration) files.calibration = findBySuffix(root, "camchain-imucam.yaml");
  files.groundtruth = firstExisting(root, {"groundtruth.txt", "stamped_groundtruth.txt"});
  if (!files.groundtruth) files.groundtruth = findBySuffix(root, "_gt.hdf5");
  return files;
}

bool isKalibrCalibration(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

std::pair<int, int> sensorSizeFromCalibration(const DatasetFiles& files) {
  if (!files.calibration || !isKalibrCalibration(*files.calibration)) return {0, 0};
  const CameraModel camera = readKalibrCalibration(*files.calibration);
  return {camera.width(), camera.height()};
}

}  // namespace asynevo
