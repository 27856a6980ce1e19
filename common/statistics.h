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

}  // namespace wallcal
