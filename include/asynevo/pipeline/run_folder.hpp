#pragma once
// Writes a run folder (DESIGN.md §1; formats in docs/pipeline.md §Run folder). The streaming files are
// written as the pipeline produces them; the trajectory and velocities are flushed after every batch of
// final knots and timing.csv after every batch of update records, so a run that stops early (or is
// killed) leaves valid partial files (tracks.txt is buffered and may lose its last lines):
//
//   stamped_traj_estimate.txt  TUM "t tx ty tz qx qy qz qw", one line per final knot (T_w_c)
//   velocities.txt             "t vx vy vz wx wy wz", body-frame twist per final knot
//   tracks.txt                 "id t x y", every frontend measurement, raw pixels, in production order
//   backend_feed.txt           "t n", every time marker with the number of tracks.txt lines the backend
//                              had taken before advancing to it (bench_replay_tracks replays the
//                              backend's exact call sequence from the two files)
//   timing.csv                 one row per backend update
// and at the end: landmarks.ply, stats.json, config.yaml, stamped_groundtruth.txt (when known).

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/core/config/config.hpp"
#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/pipeline/pipeline.hpp"

namespace asynevo::pipeline {

/// Header of timing.csv (the row layout of RunFolderWriter::onUpdateRecords).
constexpr const char* kTimingCsvHeader =
    "t_s,window_knots,landmarks,measurements,iterations,triangulate_ms,marginalize_ms,solve_ms,total_ms,"
    "solve_build_ms,solve_residuals_ms,solve_jacobians_ms,solve_linear_ms,solve_other_ms,outliers_ms";

/// Median, 95th percentile and maximum of the backend's per-update total time.
struct UpdateTimeStats {
  uint64_t updates = 0;
  double median_ms = 0, p95_ms = 0, max_ms = 0, mean_ms = 0;
  int max_window_knots = 0;
};

class RunFolderWriter final : public PipelineOutput {
 public:
  /// Creates `dir` if needed and opens the streaming files. Throws Error when it cannot.
  explicit RunFolderWriter(const std::string& dir);
  ~RunFolderWriter() override;
  RunFolderWriter(const RunFolderWriter&) = delete;
  RunFolderWriter& operator=(const RunFolderWriter&) = delete;

  void onMeasurement(const TrackMeasurement& m) override;
  void onMarker(int64_t t_ns) override;
  void onFinalKnots(const std::vector<backend::Knot>& knots) override;
  void onUpdateRecords(const std::vector<backend::UpdateRecord>& records) override;
  void onLandmarks(const std::vector<backend::LandmarkPoint>& landmarks) override;

  /// Writes landmarks.ply and closes the streaming files. Throws Error on a write failure.
  void close();
  void writeConfig(const Config& config) const;
  void writeText(const std::string& name, const std::string& text) const;
  void writeGroundTruth(const StampedTrajectory& groundtruth) const;

  std::string path(const std::string& name) const;
  uint64_t knotsWritten() const { return knots_; }
  uint64_t measurementsWritten() const { return measurements_; }
  uint64_t landmarksWritten() const { return landmarks_; }
  int64_t lastKnotNs() const { return last_knot_ns_; }
  int64_t firstKnotNs() const { return first_knot_ns_; }
  UpdateTimeStats updateTimeStats() const;

 private:
  std::FILE* open(const std::string& name);
  void writeLandmarks();
  std::string dir_;
  std::FILE* traj_ = nullptr;
  std::FILE* velocities_ = nullptr;
  std::FILE* tracks_ = nullptr;
  std::FILE* feed_ = nullptr;
  std::FILE* timing_ = nullptr;
  uint64_t knots_ = 0;
  uint64_t measurements_ = 0;
  int64_t first_knot_ns_ = 0;
  int64_t last_knot_ns_ = 0;
  std::vector<double> total_ms_;
  int max_window_knots_ = 0;
  /// landmarks.ply's rows as they come (an anonymous temporary file): the header that counts them is
  /// written at close, and the run holds none of them in memory
  std::FILE* landmark_rows_ = nullptr;
  uint64_t landmarks_ = 0;
};

/// Minimal JSON text building (no library needed): an object written key by key.
class JsonObject {
 public:
  JsonObject& add(const std::string& key, const std::string& value);
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, int64_t value);
  JsonObject& add(const std::string& key, uint64_t value);
  JsonObject& add(const std::string& key, int value) { return add(key, static_cast<int64_t>(value)); }
  JsonObject& add(const std::string& key, bool value);
  JsonObject& addObject(const std::string& key, const JsonObject& object);
  /// An array of objects (one per line).
  JsonObject& addArray(const std::string& key, const std::vector<JsonObject>& items);
  /// Pretty text with `indent` spaces of nesting.
  std::string str(int indent = 0) const;

  static std::string quote(const std::string& text);

 private:
  std::vector<std::pair<std::string, std::string>> fields_;  ///< key, JSON value text
  std::vector<bool> nested_;
  std::vector<JsonObject> objects_;
  std::vector<std::vector<JsonObject>> arrays_;  ///< field text "[k" names arrays_[k]
};

}  // namespace asynevo::pipeline
