#include "asynevo/eval/statistics.hpp"

#include <algorithm>
#include <cmath>

namespace asynevo::eval {

Stats computeStats(const std::vector<double>& values) {
  Stats s;
  const std::size_t n = values.size();
  s.num_samples = n;
  if (n == 0) return s;
  double sum = 0.0, sum_sq = 0.0;
  s.min = values.front();
  s.max = values.front();
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  const double nd = static_cast<double>(n);
  s.rmse = std::sqrt(sum_sq / nd);
  s.mean = sum / nd;
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / nd);
  s.median = percentile(values, 50.0);
  return s;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double frac = rank - static_cast<double>(lo);
  return values[lo] + (values[hi] - values[lo]) * frac;
}

}  // namespace asynevo::eval
