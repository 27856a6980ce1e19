// SPDX-License-Identifier: Apache-2.0
#pragma once
// One standing scan's wall observation whose position carries the white noise of the two GNSS
// fixes it was interpolated between as parameters, not as covariance: several scanners' standing
// scans between the same two fixes share that noise, so it is one error for all of them
// (solvers/joint_mounts.cc). Wraps a WallSliceCost of that one scan:
//   b_eff = b + (1 − f) w_a + f w_b     the GNSS error seen by the scan (m, [east, north]): the
//                                       slice's bias b plus the white errors w_a, w_b of the
//                                       fixes before and after the scan's stamp, f its fraction
//                                       of the way between them (the pose's linear interpolation)
// and evaluates the wrapped cost at b_eff (measured = true + error, as wall_line_cost.h has b).
// The residuals, their units and the robust loss are the wrapped cost's; its covariance must
// leave out the GNSS white noise carried here (ObservationCovariance with GnssWhite::kShared).
//
// Parameter blocks: the six of WallSliceCost (mount 3, wall 2, bias 2, time 2, heading offset 1,
// drift 1), then w_a (2), w_b (2).

#include <ceres/cost_function.h>

#include <memory>

#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {

class EpochNoiseCost : public ceres::CostFunction {
 public:
  // fix_fraction f in [0, 1].
  EpochNoiseCost(std::unique_ptr<WallSliceCost> scan, double fix_fraction);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::unique_ptr<WallSliceCost> scan_;
  double fix_fraction_;
};

}  // namespace wallcal::solvers
