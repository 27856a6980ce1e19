// SPDX-License-Identifier: Apache-2.0
#pragma once
// The rho a unit's range-scale error multiplies in the joint adjustment (solvers/unit_range_cost.h:
// a scale error δk moves a scan's line by rho·δk). The scan's own measured rho will not do: its
// line-fit noise is also its residual's, and the product is an error in the variables. The two
// scanners' lines of one instant pin the apparent layout between them closely (their shared GNSS
// white noise cancels), so only a sliver of the rhos' spread tells the units' common scale apart
// from the length of the transform between them, and the noise, squared, reads as a scale: +0.005
// (the preset's 1σ) on the URG-04LX benchmark's sessions whose units are exact, and a relative
// transform 0.5 % short. The rho the run's mount predicts will not do alone either: it carries
// the pose's RTK error, centimetres. So each scan gets a reference rho without its own noise:
//   standing: the mean measured rho of the other scans of its dwell on that wall (the vehicle
//             stands: the true rho is one);
//   moving:   its predicted rho plus the mean of measured minus predicted over the other moving
//             scans on that wall within `window_s` of its stamp (the pose's slowly changing RTK
//             error leaves that difference alone);
//   alone (no other scan in its group): its own measured rho.
// A reference is off the true rho by the others' noise and by what the pose's error does within
// the window, millimetres at most: times a δk of 10⁻³, micrometres.

#include <vector>

#include "calib/observation.h"
#include "solvers/wall_line_cost.h"

namespace wallcal::solvers {

// One reference rho (m) per observation; observations[i] and measurements[i] are the same scan,
// `walls` the session's (a moving scan's prediction is calib::PredictRho with `mount`).
std::vector<double> UnitScaleReferences(const std::vector<calib::WallObservation>& observations,
                                        const std::vector<WallLineMeasurement>& measurements,
                                        const std::vector<calib::WallGeometry>& walls,
                                        const calib::Mount& mount, double window_s);

}  // namespace wallcal::solvers
