#pragma once
// Summary statistics of an error vector, defined as rpg_trajectory_evaluation's
// results_writer.compute_statistics: rmse = sqrt(Σx²/n), mean, median (mean of the two middle values
// for even n), std = population standard deviation (numpy's default ddof = 0), min, max.

#include <cstddef>
#include <vector>

namespace asynevo::eval {

struct Stats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  std::size_t num_samples = 0;  ///< 0: no samples, every other field is meaningless (0)
};

/// Statistics of `values` (any order). Empty input gives num_samples = 0.
Stats computeStats(const std::vector<double>& values);

/// Percentile p ∈ [0, 100] with linear interpolation between closest ranks (numpy.percentile's
/// default). Empty input gives 0.
double percentile(std::vector<double> values, double p);

}  // namespace asynevo::eval
