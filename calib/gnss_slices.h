// SPDX-License-Identifier: Apache-2.0
#pragma once
// Finer GNSS-error slices for an adjustment that needs them. The pose interpolator puts each
// observation in a slice of alignment.segment_max_s on one time grid over the log
// (VehiclePose::gnss_segment = floor((stamp − start) / slice)). RefineGnssSlices splits every
// slice into `parts` equal sub-slices on the same grid, numbered so that they nest: sub-slice
// id = slice id × parts + its index within the slice (slice id = sub-slice id / parts).

#include <vector>

#include "calib/observation.h"

namespace wallcal::calib {

// How many parts a slice of slice_s needs so that none is longer than max_s (>= 1; 1 when
// max_s >= slice_s or either is not positive).
int SliceParts(double slice_s, double max_s);

// Moves each observation with a GNSS slice (gnss_segment >= 0) into its sub-slice; the grid is
// start_s (PoseInterpolator::start_s) and slice_s (the slicing the poses were made with).
// Observations without a slice are left as they are.
void RefineGnssSlices(double start_s, double slice_s, int parts,
                      std::vector<WallObservation>* observations);

}  // namespace wallcal::calib
