#include "asynevo/io/dataset.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/groundtruth_reader.hpp"
#include "asynevo/io/rosbag_topics.hpp"

namespace asynevo {

namespace fs = std::filesystem;

const char* const kEventFileNames =
    "events.aevt, events.txt, events.raw or another *.raw, events.dat, *_td.dat, *_cd.dat, *.aedat4, *.bag, *_data.hdf5, events.h5 or *_data.h5";

namespace {

std::optional<std::string> firstExisting(const fs::path& dir, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    if (fs::is_regular_file(dir / name)) return (dir / name).string();
  }
  return std::nullopt;
}

bool endsWith(const std::string& name, const std::string& suffix) {
  return name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// MVSEC names its files <sequence>_data.hdf5 and <sequence>_gt.hdf5.
std::optional<std::string> findBySuffix(const fs::path& dir, const std::string& suffix) {
  std::optional<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && endsWith(name, suffix)) {
      if (!found || entry.path().string() < *found) found = entry.path().string();  // deterministic choice
    }
  }
  return found;
}

/// The event formats a folder file name stands for ("" = not an event file). The reader still detects
/// the format by content (--format auto); the name only finds the file.
std::string eventFileKind(const std::string& name) {
  if (name == "events.aevt") return "aevt";
  if (name == "events.txt") return "ecd";
  if (endsWith(name, ".raw")) return "raw";  // Prophesee RAW, EVT 3.0 or 2.0
  if (name == "events.dat" || endsWith(name, "_td.dat") || endsWith(name, "_cd.dat")) return "dat";
  if (endsWith(name, ".aedat4")) return "aedat4";  // iniVation AEDAT 4.0
  if (endsWith(name, ".bag")) return "rosbag";      // ROS1 bag
  if (endsWith(name, "_data.hdf5")) return "mvsec";
  if (name == "events.h5" || endsWith(name, "_data.h5")) return "dsec";  // DSEC-style HDF5 (DSEC events.h5, M3ED)
  return "";
}

/// Whether --format narrows the folder's candidates: "auto" does not, and neither does an unknown name
/// (the reader factory reports it with the list of formats).
bool formatFilters(const std::string& format) {
  static const char* const kFormats[] = {"ecd", "mvsec", "aevt", "evt3", "evt2", "dat", "aedat4", "rosbag", "dsec"};
  return std::find(std::begin(kFormats), std::end(kFormats), format) != std::end(kFormats);
}

bool kindMatchesFormat(const std::string& kind, const std::string& format) {
  if (!formatFilters(format)) return true;
  if (kind == "raw") return format == "evt3" || format == "evt2";
  return kind == format;
}

std::string findEventFile(const fs::path& dir, const std::string& format) {
  std::vector<std::string> candidates;  // file names, sorted
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    const std::string kind = eventFileKind(name);
    if (entry.is_regular_file() && !kind.empty() && kindMatchesFormat(kind, format)) candidates.push_back(name);
  }
  std::sort(candidates.begin(), candidates.end());
  const std::string of_format = formatFilters(format) ? " for --format " + format : "";
  if (candidates.empty()) {
    throw InputError(dir.string(), "no event file in this folder" + of_format + " (expected " + kEventFileNames +
                                       "; or pass the event file itself as --dataset)");
  }
  // events.aevt is the cache 'asynevo convert' writes next to the recording: it is the same events, read faster.
  if (std::find(candidates.begin(), candidates.end(), "events.aevt") != candidates.end())
    return (dir / "events.aevt").string();
  if (candidates.size() > 1) {
    std::string list;
    for (const std::string& name : candidates) list += (list.empty() ? "" : ", ") + name;
    throw InputError(dir.string(), "several event files in this folder" + of_format + " (" + list +
                                       "): pass the one to read as --dataset FOLDER/FILE, or choose the format "
                                       "with --format");
  }
  return (dir / candidates.front()).string();
}

}  // namespace

DatasetFiles resolveDataset(const std::string& path, const std::string& format) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw InputError(path, "no such file or folder");
  DatasetFiles files;
  if (fs::is_directory(p, ec)) {
    files.root = p.string();
    files.events = findEventFile(p, format);
  } else {
    files.events = p.string();
    files.root = p.parent_path().empty() ? "." : p.parent_path().string();
  }
  const fs::path root(files.root);
  files.calibration = firstExisting(root, {"calib.txt", "camchain.yaml", "calib.yaml"});
  if (!files.calibration) files.calibration = findBySuffix(root, "camchain-imucam.yaml");
  files.groundtruth = firstExisting(root, {"groundtruth.txt", "stamped_groundtruth.txt"});
  if (!files.groundtruth) files.groundtruth = findBySuffix(root, "_gt.hdf5");
  files.sensor = firstExisting(root, {"sensor.yaml"});
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

DatasetCalibration chooseDatasetCalibration(const DatasetFiles& files, const std::string& calib,
                                            const std::string& camera_info_topic, const std::string& event_topic) {
  DatasetCalibration result;
  const bool bag = isRosbag(files.events);
  if (!camera_info_topic.empty()) {
    if (!calib.empty()) {
      throw ConfigError(std::string("--calib ") + calib + " and " + kCameraInfoTopicFlag + " " + camera_info_topic +
                        " both name the calibration: give one of them");
    }
    if (!bag) {
      throw InputError(files.events, std::string(kCameraInfoTopicFlag) + " '" + camera_info_topic +
                                         "' names a topic of a ROS bag, but the events file is not a ROS bag");
    }
    result.bag = readRosbagCalibration(files.events, camera_info_topic, event_topic);
    if (files.calibration)
      result.note = "the file " + *files.calibration + " is not used (" + kCameraInfoTopicFlag + " given)";
    return result;
  }
  if (!calib.empty() || files.calibration) {
    result.file = !calib.empty() ? calib : *files.calibration;
    if (bag) {
      std::string list;
      for (const std::string& t : rosbagCameraInfoTopics(files.events)) list += (list.empty() ? "" : ", ") + t;
      if (!list.empty()) {
        result.note = "the bag's sensor_msgs/CameraInfo topic(s) " + list + " not used: the file wins (" +
                      kCameraInfoTopicFlag + " NAME reads the bag's)";
      }
    }
    return result;
  }
  if (bag) {
    result.bag = readRosbagCalibration(files.events, "", event_topic);
    if (result.bag) result.note = result.bag->note;
  }
  return result;
}

void checkGroundTruthChoice(const DatasetFiles& files, const std::string& gt_topic) {
  const bool bag = isRosbag(files.events);
  if (!gt_topic.empty() && !bag) {
    throw InputError(files.events, std::string(kGroundTruthTopicFlag) + " '" + gt_topic +
                                       "' names a topic of a ROS bag, but the events file is not a ROS bag");
  }
  if (bag && (!gt_topic.empty() || !files.groundtruth)) checkRosbagPoseTopic(files.events, gt_topic);
}

std::optional<DatasetGroundTruth> loadDatasetGroundTruth(const DatasetFiles& files, const std::string& gt_topic) {
  checkGroundTruthChoice(files, gt_topic);
  const bool bag = isRosbag(files.events);
  DatasetGroundTruth gt;
  if (bag && !gt_topic.empty()) {
    std::optional<BagGroundTruth> poses = readRosbagGroundTruth(files.events, gt_topic);
    gt.poses = std::move(poses->poses);  // a named topic is found or the read throws
    gt.source = bagTopicSource(files.events, poses->topic);
    if (files.groundtruth) gt.note = "the file " + *files.groundtruth + " is not used (" + kGroundTruthTopicFlag + " given)";
    return gt;
  }
  if (files.groundtruth) {
    gt.poses = readGroundTruth(*files.groundtruth);
    gt.source = *files.groundtruth;
    if (bag) {
      const std::vector<std::string> topics = rosbagPoseTopics(files.events);
      std::string list;
      for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
      if (!list.empty()) {
        gt.note = "the bag's pose topic(s) " + list + " not used: the file beside the bag wins (" +
                  kGroundTruthTopicFlag + " NAME reads the bag's)";
      }
    }
    return gt;
  }
  if (!bag) return std::nullopt;
  std::optional<BagGroundTruth> poses = readRosbagGroundTruth(files.events);
  if (!poses) return std::nullopt;
  gt.poses = std::move(poses->poses);
  gt.source = bagTopicSource(files.events, poses->topic);
  return gt;
}

}  // namespace asynevo
