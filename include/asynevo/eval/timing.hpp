#pragma once
// Runtime statistics from a run folder's timing.csv: one row per backend update, a header row, the
// event time in seconds in the first column, then any columns; columns whose name ends in "_ms"
// are per-stage milliseconds, "total_ms" is the whole update. Other numeric columns (e.g. the
// window size) get the same statistics.

#include <cstddef>
#include <string>
#include <vector>

namespace asynevo::eval {

struct ColumnStats {
  std::string name;
  double mean = 0.0, median = 0.0, p95 = 0.0, max = 0.0, sum = 0.0;
};

struct TimingStats {
  std::size_t updates = 0;  ///< data rows
  double t_first_s = 0.0, t_last_s = 0.0;
  std::vector<ColumnStats> stages;  ///< "*_ms" columns, in file order (total_ms included)
  std::vector<ColumnStats> others;  ///< other numeric columns except the time
  bool has_total = false;
  double total_ms_sum = 0.0;
  /// Backend real-time factor: Σ total_ms / 1000 / (t_last − t_first); < 1 is faster than real
  /// time. 0 when there is no total_ms column or the span is 0.
  double backend_real_time_factor = 0.0;
};

/// Reads timing.csv. Throws InputError (file and line) on a missing/empty file, a missing header,
/// a row with the wrong number of fields or a non-numeric value.
TimingStats readTimingStats(const std::string& path);

}  // namespace asynevo::eval
