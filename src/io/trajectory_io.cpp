#include "asynevo/io/trajectory_io.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string_view>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo {

namespace {

constexpr std::size_t kMaxFields = 16;

/// Splits `line` on spaces and tabs (a trailing '\r' is ignored). Returns the number of fields,
/// which may exceed kMaxFields (only the first kMaxFields are stored).
std::size_t splitFields(std::string_view line, std::string_view* fields) {
  std::size_t count = 0;
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= n) break;
    const std::size_t begin = i;
    while (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (count < kMaxFields) fields[count] = line.substr(begin, i - begin);
    ++count;
  }
  return count;
}

bool isSkippable(std::string_view line) {
  for (char c : line) {
    if (c == '#') return true;
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;  // blank
}

/// A locale-independent, exact (round-to-nearest) parse of one decimal number.
bool parseDouble(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

/// A line-oriented reader of numeric records with a fixed field count and a time in field 0.
class RecordReader {
 public:
  RecordReader(std::string path, std::size_t fields, const char* layout)
      : path_(std::move(path)), expected_fields_(fields), layout_(layout), in_(path_) {
    if (!in_) throw InputError(path_, "cannot open file");
  }

  /// Reads the next record into `values` (values[0] is unused: the time goes to t_ns). Returns
  /// false at the end of the file.
  bool next(int64_t& t_ns, double* values, TrajectoryReadReport& report) {
    std::string_view fields[kMaxFields];
    while (std::getline(in_, line_)) {
      ++line_number_;
      if (isSkippable(line_)) {
        ++report.skipped_lines;
        continue;
      }
      const std::size_t count = splitFields(line_, fields);
      if (count != expected_fields_) {
        throw error(fmt::format("expected {} fields ({}), found {}", expected_fields_, layout_, count));
      }
      const auto t = parseSecondsToNs(fields[0]);
      if (!t) throw error(fmt::format("time '{}' is not a finite number of seconds", fields[0]));
      for (std::size_t k = 1; k < count; ++k) {
        if (!parseDouble(fields[k], values[k])) {
          throw error(fmt::format("field {} '{}' is not a number", k + 1, fields[k]));
        }
        if (!std::isfinite(values[k])) throw error(fmt::format("field {} is {}", k + 1, fields[k]));
      }
      if (have_previous_ && *t < previous_t_ns_) {
        char now[32], before[32];
        formatNsAsSeconds(*t, now);
        formatNsAsSeconds(previous_t_ns_, before);
        throw error(
            fmt::format("time {} s is earlier than the previous record's {} s (line {}); "
                        "records must be sorted by time",
                        now, before, previous_line_));
      }
      have_previous_ = true;
      previous_t_ns_ = *t;
      previous_line_ = line_number_;
      t_ns = *t;
      ++report.records;
      return true;
    }
    if (in_.bad()) throw InputError(path_, "read error");
    return false;
  }

  InputError error(std::string message) const {
    return InputError::atLine(path_, line_number_, std::move(message));
  }
  uint64_t lineNumber() const { return line_number_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::size_t expected_fields_;
  const char* layout_;
  std::ifstream in_;
  std::string line_;
  uint64_t line_number_ = 0;
  bool have_previous_ = false;
  int64_t previous_t_ns_ = 0;
  uint64_t previous_line_ = 0;
};

StampedTrajectory readPoseFile(const std::string& path, TrajectoryReadReport* report_out) {
  TrajectoryReadReport report;
  RecordReader reader(path, 8, "t tx ty tz qx qy qz qw");
  StampedTrajectory trajectory;
  double v[8];
  int64_t t_ns = 0;
  while (reader.next(t_ns, v, report)) {
    StampedPose pose;
    pose.t_ns = t_ns;
    pose.p_w_c = Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
    // Scaled by the largest component first: q.norm() squares the components, which overflows to inf for
    // components above ~1e154 (the quaternion then became 0 / inf = 0 and was accepted; found 2026-11-26
    // by the tum_trajectory fuzz harness) and underflows to 0 below ~1e-154.
    const double scale = q.coeffs().cwiseAbs().maxCoeff();
    const double unit_norm = scale > 0 ? (q.coeffs() / scale).norm() : 0.0;  // in [1, 2] unless zero
    const double norm = scale * unit_norm;
    if (!(norm > 1e-12)) throw reader.error("zero quaternion (qx qy qz qw all 0)");
    if (!std::isfinite(norm)) throw reader.error("quaternion too large to normalize (its norm overflows)");
    const double norm_error = std::fabs(norm - 1.0);
    if (norm_error > report.max_quaternion_norm_error) report.max_quaternion_norm_error = norm_error;
    if (norm_error > kQuaternionNormTolerance) {
      if (report.normalized_quaternions == 0) report.first_normalized_line = reader.lineNumber();
      ++report.normalized_quaternions;
    }
    q.coeffs() = (q.coeffs() / scale) / unit_norm;
    pose.q_w_c = q;
    trajectory.push_back(pose);
  }
  if (trajectory.empty()) throw InputError(path, "no poses in file (empty or only comments)");
  if (report_out) *report_out = report;
  return trajectory;
}

std::FILE* openForWriting(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw Error(fmt::format("{}: cannot open file for writing", path));
  return f;
}

void writeHeader(std::FILE* f, const std::string& header) {
  if (header.empty()) return;
  std::size_t begin = 0;
  while (begin <= header.size()) {
    const std::size_t end = std::min(header.find('\n', begin), header.size());
    fmt::print(f, "# {}\n", std::string_view(header).substr(begin, end - begin));
    begin = end + 1;
  }
}

void closeChecked(std::FILE* f, const std::string& path) {
  const bool failed = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || failed) throw Error(fmt::format("{}: write failed", path));
}

}  // namespace

StampedTrajectory readTumTrajectory(const std::string& path, TrajectoryReadReport* report) {
  return readPoseFile(path, report);
}

StampedTrajectory readEcdGroundTruth(const std::string& path, TrajectoryReadReport* report) {
  return readPoseFile(path, report);
}

std::vector<StampedTwist> readVelocities(const std::string& path, TrajectoryReadReport* report_out) {
  TrajectoryReadReport report;
  RecordReader reader(path, 7, "t vx vy vz wx wy wz");
  std::vector<StampedTwist> twists;
  double v[7];
  int64_t t_ns = 0;
  while (reader.next(t_ns, v, report)) {
    StampedTwist twist;
    twist.t_ns = t_ns;
    twist.v_c = Eigen::Vector3d(v[1], v[2], v[3]);
    twist.w_c = Eigen::Vector3d(v[4], v[5], v[6]);
    twists.push_back(twist);
  }
  if (twists.empty()) throw InputError(path, "no velocities in file (empty or only comments)");
  if (report_out) *report_out = report;
  return twists;
}

void writeTumTrajectory(const std::string& path, const StampedTrajectory& trajectory,
                        const std::string& header) {
  std::FILE* f = openForWriting(path);
  writeHeader(f, header);
  char t[32];
  for (const StampedPose& pose : trajectory) {
    formatNsAsSeconds(pose.t_ns, t);
    const Eigen::Quaterniond& q = pose.q_w_c;
    fmt::print(f, "{} {} {} {} {} {} {} {}\n", t, pose.p_w_c.x(), pose.p_w_c.y(), pose.p_w_c.z(), q.x(),
               q.y(), q.z(), q.w());
  }
  closeChecked(f, path);
}

void writeVelocities(const std::string& path, const std::vector<StampedTwist>& twists,
                     const std::string& header) {
  std::FILE* f = openForWriting(path);
  writeHeader(f, header);
  char t[32];
  for (const StampedTwist& twist : twists) {
    formatNsAsSeconds(twist.t_ns, t);
    fmt::print(f, "{} {} {} {} {} {} {}\n", t, twist.v_c.x(), twist.v_c.y(), twist.v_c.z(), twist.w_c.x(),
               twist.w_c.y(), twist.w_c.z());
  }
  closeChecked(f, path);
}

}  // namespace asynevo
