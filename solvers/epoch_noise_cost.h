// SPDX-License-Identifier: Apache-2.0
#pragma once
// One scan's wall observation whose pose carries the white noise of the GNSS fixes and heading
// samples it was interpolated between as parameters, not as covariance: several scanners' scans
// of one instant come from the same fixes and samples, so that noise is one error for all of
// them (solvers/joint_mounts.cc). Wraps a WallSliceCost of that one scan:
//   b_eff = b + (1 − f) w_a + f w_b     the GNSS error seen by the scan (m, [east, north]): the
//                                       slice's bias b plus the white errors w_a, w_b of the
//                                       fixes before and after, f its fraction of the way
//                                       between them
//   h_eff = h + (1 − g) η_a + g η_b     the heading error (rad): the dwell's offset h (a moving
//                                       scan: the constant zero block) plus the white errors of
//                                       the heading samples before and after, at fraction g
// and evaluates the wrapped cost at b_eff, h_eff (measured = true + error, as wall_line_cost.h
// has b and h). The residuals, their units and the robust loss are the wrapped cost's; its
// covariance must leave out the white noise carried here (ObservationCovariance's `shared`).
//
// Parameter blocks: the six of WallSliceCost (mount 3, wall 2, bias 2, time 2, heading offset 1,
// drift 1), then w_a (2), w_b (2), η_a (1), η_b (1). A scan whose fixes or heading samples are
// not shared passes constant zero blocks there.

#include <ceres/cost_function.h>

#include <memory>

#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {

class EpochNoiseCost : public ceres::CostFunction {
 public:
  // fix_fraction f and heading_fraction g in [0, 1].
  EpochNoiseCost(std::unique_ptr<WallSliceCost> scan, double fix_fraction,
                 double heading_fraction);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::unique_ptr<WallSliceCost> scan_;
  double fix_fraction_;
  double heading_fraction_;
};

}  // namespace wallcal::solvers
