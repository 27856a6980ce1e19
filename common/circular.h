// SPDX-License-Identifier: Apache-2.0
#pragma once
// Circular statistics of angles (rad): the mean direction and the extent of a set of angles
// about it, for headings that straddle north and relative angles that straddle ±180°.

#include <vector>

namespace wallcal {

// Circular mean of angles (rad), in (−π, π]; 0 for an empty set.
double CircularMean(const std::vector<double>& angles_rad);

// The smallest and largest angle about the circular mean: min_rad = mean + (most negative
// deviation), max_rad = mean + (most positive deviation), deviations in (−π, π]. Both 0 for an
// empty set. The caller chooses how to print them (headings in [0, 360), relative angles in
// (−180, 180]).
struct CircularExtent {
  double mean_rad = 0.0;
  double min_rad = 0.0;
  double max_rad = 0.0;
  bool empty = true;
};
CircularExtent CircularExtentOf(const std::vector<double>& angles_rad);

// The narrowest arc holding every angle (rad, each within one turn of the others): the circle
// minus the widest empty gap between neighbours. It runs counter-clockwise from start_rad to
// end_rad (both angles of the set) and is width_rad = 2π − the widest gap wide; 0 for one
// angle or none.
struct CircularArc {
  double start_rad = 0.0;
  double end_rad = 0.0;
  double width_rad = 0.0;
};
CircularArc NarrowestArc(std::vector<double> angles_rad);

}  // namespace wallcal
