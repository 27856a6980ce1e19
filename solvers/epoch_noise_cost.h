// SPDX-License-Identifier: Apache-2.0
#pragma once
// One scan's wall observation whose pose carries the white noise of the GNSS fixes and heading
// samples it was interpolated between as parameters, not as covariance: several scanners' scans
// of one instant come from the same fixes and samples, so that noise is one error for all of
// them (solvers/joint_mounts.cc). Wraps a WallSliceCost of that one scan:
//   b_eff = b + Σ_j u_j w_j             the GNSS error seen by the scan (m, [east, north]): the
//                                       slice's bias b plus the white errors w_j of the fixes
//                                       k − 1 .. k + 2, weighted as the interpolation weighted
//                                       them (u = (0, 1 − f, f, 0) linear, Hermite weights for a
//                                       moving pose from cubics: VehiclePose::gnss_fix_weights)
//   h_eff = h + Σ_j v_j η_j             the heading error (rad): the dwell's offset h (a moving
//                                       scan: the constant zero block) plus the white errors of
//                                       the heading samples k − 1 .. k + 2 with their weights
// and evaluates the wrapped cost at b_eff, h_eff (measured = true + error, as wall_line_cost.h
// has b and h). The residuals, their units and the robust loss are the wrapped cost's; its
// covariance must leave out the white noise carried here (ObservationCovariance's `shared`).
//
// Parameter blocks: the six of WallSliceCost (mount 3, wall 2, bias 2, time 2, heading offset 1,
// drift 1), then w_{k−1} .. w_{k+2} (2 each), η_{k−1} .. η_{k+2} (1 each). A sample of weight 0
// (or a stream not shared) takes a constant zero block there.

#include <ceres/cost_function.h>

#include <array>
#include <memory>

#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {

class EpochNoiseCost : public ceres::CostFunction {
 public:
  // The weights of the fixes and of the heading samples k − 1 .. k + 2.
  EpochNoiseCost(std::unique_ptr<WallSliceCost> scan, const std::array<double, 4>& fix_weights,
                 const std::array<double, 4>& sample_weights);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::unique_ptr<WallSliceCost> scan_;
  std::array<double, 4> fix_weights_;
  std::array<double, 4> sample_weights_;
};

}  // namespace wallcal::solvers
