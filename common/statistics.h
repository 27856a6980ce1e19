// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small order statistics shared by the analysis steps.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace wallcal {

// The median of `values` (the mean of the two middle values for an even count); NaN when empty.
inline double Median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = values.size() / 2;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(mid);
  std::nth_element(values.begin(), middle, values.end());
  double median = *middle;
  if (values.size() % 2 == 0) median = 0.5 * (median + *std::max_element(values.begin(), middle));
  return median;
}

// The value at index size/2 of the sorted values (for an even count the upper of the two middle
// ones: always one of the values); `empty_value` when there are none.
inline double UpperMedian(std::vector<double> values, double empty_value) {
  if (values.empty()) return empty_value;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace wallcal
