// SPDX-License-Identifier: Apache-2.0
#include "common/circular.h"

#include <algorithm>
#include <cmath>

#include "common/angles.h"

namespace wallcal {

double CircularMean(const std::vector<double>& angles_rad) {
  if (angles_rad.empty()) return 0.0;
  double sx = 0.0, sy = 0.0;
  for (double a : angles_rad) {
    sx += std::cos(a);
    sy += std::sin(a);
  }
  return std::atan2(sy, sx);
}

CircularExtent CircularExtentOf(const std::vector<double>& angles_rad) {
  CircularExtent extent;
  if (angles_rad.empty()) return extent;
  extent.empty = false;
  extent.mean_rad = CircularMean(angles_rad);
  double lo = 0.0, hi = 0.0;
  for (double a : angles_rad) {
    const double d = WrapAngle(a - extent.mean_rad);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  extent.min_rad = extent.mean_rad + lo;
  extent.max_rad = extent.mean_rad + hi;
  return extent;
}

CircularArc NarrowestArc(std::vector<double> angles_rad) {
  CircularArc arc;
  if (angles_rad.empty()) return arc;
  std::sort(angles_rad.begin(), angles_rad.end());
  double widest_gap_rad = angles_rad.front() + kTwoPi - angles_rad.back();
  arc.start_rad = angles_rad.front();
  arc.end_rad = angles_rad.back();
  for (size_t k = 1; k < angles_rad.size(); ++k) {
    const double gap_rad = angles_rad[k] - angles_rad[k - 1];
    if (gap_rad > widest_gap_rad) {
      widest_gap_rad = gap_rad;
      arc.start_rad = angles_rad[k];
      arc.end_rad = angles_rad[k - 1];
    }
  }
  arc.width_rad = kTwoPi - widest_gap_rad;
  return arc;
}

}  // namespace wallcal
