#pragma once
// A dataset on disk: an ECD-style folder (an event file, calib.txt or a camchain, optional
// groundtruth.txt and sensor.yaml) or a single event file. Resolving a path tells which files play which
// role; nothing is read yet.

#include <optional>
#include <string>
#include <utility>

#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/io/rosbag_topics.hpp"

namespace asynevo {

struct DatasetFiles {
  std::string root;                        ///< the folder (or the file's folder)
  std::string events;                      ///< event file
  std::optional<std::string> calibration;  ///< calib.txt or a Kalibr camchain YAML, when present
  std::optional<std::string> groundtruth;  ///< groundtruth.txt (ECD/TUM) or MVSEC *_gt.hdf5
  std::optional<std::string> sensor;       ///< sensor.yaml (the sensor size), when present
};

/// The event-file names a folder is searched for, in the words of the error messages.
extern const char* const kEventFileNames;

/// Resolves `path`. A folder must hold an event file (kEventFileNames): events.aevt, a converted cache,
/// is taken when present; otherwise exactly one of the others must be there (several are an error that
/// lists them). `format` other than "auto" keeps only that format's files (ecd: .txt, evt3/evt2: .raw,
/// dat: .dat, mvsec: .hdf5, aevt: .aevt). A file is taken as the event file. Throws InputError when
/// nothing usable is found.
DatasetFiles resolveDataset(const std::string& path, const std::string& format = "auto");

/// True for calibration files in Kalibr camchain YAML form (by extension: .yaml / .yml).
bool isKalibrCalibration(const std::string& path);

/// The resolution of the dataset's Kalibr calibration when it has one, else {0, 0}. Commands choose the
/// size with chooseSensorSize (io/sensor_size.hpp), which ranks this below --sensor, the configuration
/// and sensor.yaml.
std::pair<int, int> sensorSizeFromCalibration(const DatasetFiles& files);

/// Where a dataset's camera calibration comes from.
struct DatasetCalibration {
  std::string file;                   ///< the calibration file ("" = the bag's CameraInfo topic, or none)
  std::optional<BagCalibration> bag;  ///< the camera of a ROS bag's CameraInfo topic, when that is the source
  std::string note;                   ///< what else was there and is not used, or how the topic was chosen
};

/// The dataset's calibration, by this rule (docs/reference/formats_rosbag.md#calibration):
///   1. `calib` (--calib FILE);
///   2. `camera_info_topic` (--camera-info-topic): that CameraInfo topic of the bag (an error with --calib, or
///      when the events file is not a ROS bag);
///   3. a calibration file beside the events (files.calibration: calib.txt, a camchain) — it wins over the
///      bag's CameraInfo topics, which `note` then names;
///   4. the bag's CameraInfo topic (readRosbagCalibration: the only one, or the one in the namespace of
///      `event_topic`, the --topic that is read).
/// Neither `file` nor `bag` set when there is none. Read errors are InputErrors.
DatasetCalibration chooseDatasetCalibration(const DatasetFiles& files, const std::string& calib,
                                            const std::string& camera_info_topic, const std::string& event_topic);

/// A dataset's ground truth and where it came from.
struct DatasetGroundTruth {
  StampedTrajectory poses;
  std::string source;  ///< the file, or "BAG (topic NAME)"
  std::string note;    ///< what else was there and is not used ("" = nothing)
};

/// The dataset's ground truth, by this rule (docs/reference/formats_rosbag.md#ground-truth):
///   1. `gt_topic` (--gt-topic) names a pose topic of the bag: that topic (an error when the events file is
///      not a ROS bag, or the topic is missing or not a pose type);
///   2. else a ground-truth file in the folder (groundtruth.txt, ..., files.groundtruth) — it wins over the
///      bag's pose topic, which `note` then names;
///   3. else the bag's only pose topic (geometry_msgs/PoseStamped, TransformStamped, nav_msgs/Odometry).
/// std::nullopt when there is none. Read errors are InputErrors.
std::optional<DatasetGroundTruth> loadDatasetGroundTruth(const DatasetFiles& files, const std::string& gt_topic = "");

/// Checks, before any event is read, what loadDatasetGroundTruth would fail on for want of a choice: an
/// InputError when --gt-topic is given but the events are not a ROS bag, when it names a topic the bag
/// lacks (or of another type or revision), or when no file wins and the bag has several pose topics.
/// Only the bag's index is read.
void checkGroundTruthChoice(const DatasetFiles& files, const std::string& gt_topic);

}  // namespace asynevo
