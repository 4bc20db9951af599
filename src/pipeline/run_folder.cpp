#include "asynevo/pipeline/run_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/core/json.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/trajectory_io.hpp"

namespace asynevo::pipeline {

namespace {

void closeChecked(std::FILE*& f, const std::string& path) {
  if (!f) return;
  const bool failed = std::ferror(f) != 0;
  const bool close_failed = std::fclose(f) != 0;
  f = nullptr;
  if (failed || close_failed) throw Error(fmt::format("{}: write failed", path));
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  // Linear interpolation between closest ranks (numpy's default).
  const double pos = p * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return values[lo] + frac * (values[hi] - values[lo]);
}

}  // namespace

RunFolderWriter::RunFolderWriter(const std::string& dir) : dir_(dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_))
    throw Error(
        fmt::format("{}: cannot create the output folder ({})", dir_, ec ? ec.message() : "not a folder"));
  traj_ = open("stamped_traj_estimate.txt");
  velocities_ = open("velocities.txt");
  tracks_ = open("tracks.txt");
  feed_ = open("backend_feed.txt");
  timing_ = open("timing.csv");
  landmark_rows_ = std::tmpfile();
  if (!landmark_rows_) throw Error(fmt::format("{}: cannot create a temporary file for landmarks.ply", dir_));
  fmt::print(traj_, "# t tx ty tz qx qy qz qw  (T_w_c, camera-to-world; one line per final knot)\n");
  fmt::print(velocities_, "# t vx vy vz wx wy wz  (body-frame twist per knot)\n");
  fmt::print(tracks_, "# id t x y  (feature measurements, raw pixel coordinates)\n");
  fmt::print(feed_, "# t n  (time marker; tracks.txt lines the backend had taken before advancing to it)\n");
  fmt::print(timing_, "{}\n", kTimingCsvHeader);
  std::fflush(traj_);
  std::fflush(velocities_);
  std::fflush(timing_);
}

RunFolderWriter::~RunFolderWriter() {
  for (std::FILE* f : {traj_, velocities_, tracks_, feed_, timing_, landmark_rows_})
    if (f) std::fclose(f);
}

std::string RunFolderWriter::path(const std::string& name) const {
  return (std::filesystem::path(dir_) / name).string();
}

std::FILE* RunFolderWriter::open(const std::string& name) {
  const std::string p = path(name);
  std::FILE* f = std::fopen(p.c_str(), "w");
  if (!f) throw Error(fmt::format("{}: cannot open file for writing", p));
  return f;
}

void RunFolderWriter::onMeasurement(const TrackMeasurement& m) {
  char t[32];
  formatNsAsSeconds(m.t_ns, t);
  // Shortest text that reads back as the same float: a replay sees exactly what the backend saw.
  fmt::print(tracks_, "{} {} {} {}\n", m.feature_id, t, m.x, m.y);
  ++measurements_;
}

void RunFolderWriter::onMarker(int64_t t_ns) {
  char t[32];
  formatNsAsSeconds(t_ns, t);
  fmt::print(feed_, "{} {}\n", t, measurements_);
}

void RunFolderWriter::onFinalKnots(const std::vector<backend::Knot>& knots) {
  char t[32];
  for (const backend::Knot& k : knots) {
    formatNsAsSeconds(k.t_ns, t);
    const auto& p = k.pose;  // [t_x t_y t_z q_x q_y q_z q_w]
    fmt::print(traj_, "{} {} {} {} {} {} {} {}\n", t, p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
    const auto& w = k.velocity;
    fmt::print(velocities_, "{} {} {} {} {} {} {}\n", t, w[0], w[1], w[2], w[3], w[4], w[5]);
    if (knots_ == 0) first_knot_ns_ = k.t_ns;
    last_knot_ns_ = k.t_ns;
    ++knots_;
  }
  // Flushed per batch: a run that stops early leaves every final knot on disk.
  std::fflush(traj_);
  std::fflush(velocities_);
}

void RunFolderWriter::onUpdateRecords(const std::vector<backend::UpdateRecord>& records) {
  char t[32];
  for (const backend::UpdateRecord& r : records) {
    formatNsAsSeconds(r.event_t_ns, t);
    fmt::print(timing_, "{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}\n", t,
               r.window_knots, r.landmarks, r.measurements, r.iterations, r.triangulate_ms, r.marginalize_ms,
               r.solve_ms, r.total_ms, r.solve_build_ms, r.solve_residuals_ms, r.solve_jacobians_ms,
               r.solve_linear_ms, r.solve_other_ms, r.outliers_ms);
    total_ms_.push_back(r.total_ms);
    max_window_knots_ = std::max(max_window_knots_, r.window_knots);
  }
  // Flushed per batch (one or a few rows per backend update, each taking milliseconds or more): a run
  // that is killed (a benchmark's time limit) keeps every complete row it produced.
  std::fflush(timing_);
}

void RunFolderWriter::onLandmarks(const std::vector<backend::LandmarkPoint>& landmarks) {
  for (const backend::LandmarkPoint& l : landmarks)
    fmt::print(landmark_rows_, "{} {} {} {} {}\n", l.p_w.x(), l.p_w.y(), l.p_w.z(), l.observations, l.id);
  landmarks_ += landmarks.size();
}

void RunFolderWriter::close() {
  closeChecked(traj_, path("stamped_traj_estimate.txt"));
  closeChecked(velocities_, path("velocities.txt"));
  closeChecked(tracks_, path("tracks.txt"));
  closeChecked(feed_, path("backend_feed.txt"));
  closeChecked(timing_, path("timing.csv"));
  writeLandmarks();
}

void RunFolderWriter::writeLandmarks() {
  if (!landmark_rows_) return;
  const std::string p = path("landmarks.ply");
  std::FILE* f = std::fopen(p.c_str(), "w");
  if (!f) throw Error(fmt::format("{}: cannot open file for writing", p));
  fmt::print(f, "ply\nformat ascii 1.0\n");
  fmt::print(f, "comment AsynEVO landmarks, world frame (map units; monocular scale)\n");
  fmt::print(f, "element vertex {}\n", landmarks_);
  fmt::print(f, "property double x\nproperty double y\nproperty double z\n");
  fmt::print(f, "property int observations\nproperty int id\nend_header\n");
  const bool rows_failed = std::ferror(landmark_rows_) != 0 || std::fflush(landmark_rows_) != 0;
  std::rewind(landmark_rows_);
  char buffer[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, landmark_rows_)) > 0) std::fwrite(buffer, 1, n, f);
  const bool read_failed = std::ferror(landmark_rows_) != 0;
  std::fclose(landmark_rows_);
  landmark_rows_ = nullptr;
  closeChecked(f, p);
  if (rows_failed || read_failed) throw Error(fmt::format("{}: write failed (temporary rows file)", p));
}

void RunFolderWriter::writeText(const std::string& name, const std::string& text) const {
  const std::string p = path(name);
  std::FILE* f = std::fopen(p.c_str(), "w");
  if (!f) throw Error(fmt::format("{}: cannot open file for writing", p));
  std::fwrite(text.data(), 1, text.size(), f);
  closeChecked(f, p);
}

void RunFolderWriter::writeConfig(const Config& config) const {
  writeText("config.yaml",
            "# AsynEVO effective configuration of this run (every value).\n" + configToYaml(config));
}

void RunFolderWriter::writeGroundTruth(const StampedTrajectory& groundtruth) const {
  writeTumTrajectory(path("stamped_groundtruth.txt"), groundtruth,
                     "t tx ty tz qx qy qz qw  (ground truth T_w_c over the event time span)");
}

UpdateTimeStats RunFolderWriter::updateTimeStats() const {
  UpdateTimeStats s;
  s.updates = total_ms_.size();
  s.max_window_knots = max_window_knots_;
  if (total_ms_.empty()) return s;
  s.median_ms = percentile(total_ms_, 0.5);
  s.p95_ms = percentile(total_ms_, 0.95);
  s.max_ms = *std::max_element(total_ms_.begin(), total_ms_.end());
  double sum = 0;
  for (double v : total_ms_) sum += v;
  s.mean_ms = sum / static_cast<double>(total_ms_.size());
  return s;
}

// --- JSON ---

std::string JsonObject::quote(const std::string& text) { return jsonQuoted(text); }

JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
  fields_.emplace_back(key, quote(value));
  nested_.push_back(false);
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, double value) {
  fields_.emplace_back(key, jsonNumber(value));
  nested_.push_back(false);
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, int64_t value) {
  fields_.emplace_back(key, fmt::format("{}", value));
  nested_.push_back(false);
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, uint64_t value) {
  fields_.emplace_back(key, fmt::format("{}", value));
  nested_.push_back(false);
  return *this;
}
JsonObject& JsonObject::add(const std::string& key, bool value) {
  fields_.emplace_back(key, value ? "true" : "false");
  nested_.push_back(false);
  return *this;
}
JsonObject& JsonObject::addObject(const std::string& key, const JsonObject& object) {
  fields_.emplace_back(key, fmt::format("{}", objects_.size()));
  nested_.push_back(true);
  objects_.push_back(object);
  return *this;
}

JsonObject& JsonObject::addArray(const std::string& key, const std::vector<JsonObject>& items) {
  fields_.emplace_back(key, fmt::format("[{}", arrays_.size()));
  nested_.push_back(true);
  arrays_.push_back(items);
  return *this;
}

std::string JsonObject::str(int indent) const {
  if (fields_.empty()) return "{}";
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    out += pad + quote(fields_[i].first) + ": ";
    const std::string& value = fields_[i].second;
    if (!nested_[i]) {
      out += value;
    } else if (value[0] != '[') {
      out += objects_[std::stoul(value)].str(indent + 2);
    } else {
      const std::vector<JsonObject>& items = arrays_[std::stoul(value.substr(1))];
      out += "[";
      for (std::size_t k = 0; k < items.size(); ++k) {
        out += (k == 0 ? "\n" : ",\n") + pad + "  " + items[k].str(indent + 4);
      }
      out += items.empty() ? "]" : "\n" + pad + "]";
    }
    out += i + 1 < fields_.size() ? ",\n" : "\n";
  }
  return out + std::string(static_cast<std::size_t>(indent), ' ') + "}";
}

}  // namespace asynevo::pipeline
