// SPDX-License-Identifier: Apache-2.0
#include "calib/gnss_slices.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

namespace wallcal::calib {

int SliceParts(double slice_s, double max_s) {
  if (!(slice_s > 0.0) || !(max_s > 0.0) || max_s >= slice_s) return 1;
  // A hair under an integer ratio is that integer (0.25 / 0.05 in floating point).
  const double parts = std::ceil(slice_s / max_s - 1e-9);
  return static_cast<int>(std::min(parts, 1000.0));
}

void RefineGnssSlices(double start_s, double slice_s, int parts,
                      std::vector<WallObservation>* observations) {
  if (parts <= 1 || !(slice_s > 0.0)) return;
  const double part_s = slice_s / parts;
  for (WallObservation& observation : *observations) {
    VehiclePose& pose = observation.pose;
    if (pose.gnss_segment < 0) continue;
    const int64_t slice = pose.gnss_segment;
    // Within its own slice by construction, whatever the rounding of the division.
    const double into_s = pose.stamp_s - start_s - static_cast<double>(slice) * slice_s;
    const double index = std::clamp(std::floor(into_s / part_s), 0.0, parts - 1.0);
    const int64_t refined = slice * parts + static_cast<int64_t>(index);
    pose.gnss_segment = static_cast<int>(std::min<int64_t>(refined, INT_MAX - 1));
  }
}

}  // namespace wallcal::calib
