#pragma once
// The upper median of a list of values: the element at index n / 2 of the sorted list, found by a
// partial sort that reorders `values` (std::nth_element). For an even count it is the larger of the two
// middle values, not their mean. The backend's tests on medians (parallax, residuals, depths) use it.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace asynevo::backend {

/// The upper median of `values` (not empty); reorders them.
inline double upperMedian(std::vector<double>& values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace asynevo::backend
