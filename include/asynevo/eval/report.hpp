#pragma once
// Evaluation outputs: eval.json (everything, including per-sample relative errors for box plots),
// YAML files shaped like rpg_trajectory_evaluation's absolute_err_statistics_<align>_<n>.yaml and
// relative_error_statistics_<len>.yaml, and a short text table for the terminal.

#include <string>

#include "asynevo/eval/evaluate.hpp"
#include "asynevo/eval/timing.hpp"

namespace asynevo::eval {

struct ReportInputs {
  std::string gt_path, est_path;
  const TimingStats* timing = nullptr;  ///< optional
};

std::string evalJson(const EvalResult& result, const ReportInputs& inputs);

/// Writes eval.json and the rpg-style YAML files into `dir` (created if missing). Returns the paths
/// written. Throws Error when a file cannot be written.
std::vector<std::string> writeEvalOutputs(const std::string& dir, const EvalResult& result,
                                          const ReportInputs& inputs);

/// A short human-readable summary (association, alignment, ATE, relative error per length).
std::string summaryTable(const EvalResult& result, const TimingStats* timing = nullptr);

}  // namespace asynevo::eval
