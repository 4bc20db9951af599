#include "asynevo/eval/timing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>

#include "asynevo/core/error.hpp"
#include "asynevo/eval/statistics.hpp"

namespace asynevo::eval {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> splitCsv(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(
        trim(line.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

bool endsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

ColumnStats columnStats(const std::string& name, const std::vector<double>& values) {
  ColumnStats c;
  c.name = name;
  const Stats s = computeStats(values);
  c.mean = s.mean;
  c.median = s.median;
  c.max = s.max;
  c.p95 = percentile(values, 95.0);
  for (double v : values) c.sum += v;
  return c;
}

}  // namespace

TimingStats readTimingStats(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  std::string line;
  uint64_t line_number = 0;
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string_view view = trim(line);
    if (view.empty() || view.front() == '#') continue;
    const auto fields = splitCsv(view);
    if (header.empty()) {
      for (auto f : fields) header.emplace_back(f);
      if (header.size() < 2)
        throw InputError::atLine(path, line_number, "expected a header with at least 2 columns");
      columns.resize(header.size());
      continue;
    }
    if (fields.size() != header.size()) {
      throw InputError::atLine(
          path, line_number,
          fmt::format("expected {} fields like the header, found {}", header.size(), fields.size()));
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      double v = 0.0;
      const auto res = std::from_chars(fields[k].data(), fields[k].data() + fields[k].size(), v);
      if (res.ec != std::errc() || res.ptr != fields[k].data() + fields[k].size() || !std::isfinite(v)) {
        throw InputError::atLine(path, line_number,
                                 fmt::format("{} '{}' is not a finite number", header[k], fields[k]));
      }
      columns[k].push_back(v);
    }
  }
  if (header.empty()) throw InputError(path, "empty file (expected a header and one row per backend update)");
  TimingStats stats;
  stats.updates = columns[0].size();
  if (stats.updates == 0) throw InputError(path, "no rows after the header");
  stats.t_first_s = columns[0].front();
  stats.t_last_s = columns[0].back();
  for (std::size_t k = 1; k < header.size(); ++k) {
    ColumnStats c = columnStats(header[k], columns[k]);
    if (endsWith(header[k], "_ms")) {
      if (header[k] == "total_ms") {
        stats.has_total = true;
        stats.total_ms_sum = c.sum;
      }
      stats.stages.push_back(std::move(c));
    } else {
      stats.others.push_back(std::move(c));
    }
  }
  const double span = stats.t_last_s - stats.t_first_s;
  if (stats.has_total && span > 0.0) stats.backend_real_time_factor = stats.total_ms_sum / 1000.0 / span;
  return stats;
}

}  // namespace asynevo::eval
