// SPDX-License-Identifier: Apache-2.0
#pragma once
// The wall observations that share all six parameter blocks (the scans of one GNSS-error slice
// on one wall: same wall, bias and heading-offset blocks) as one Ceres residual block, two
// residuals per scan. An hour-long session has 270 000 scans in 14 000 slices: one residual
// block per scan cost Ceres about 240 bytes of bookkeeping and its own product terms each.
//
// Each scan keeps its own robust loss, and the solver sees exactly what it saw with one block
// per scan and ceres::HuberLoss(k). With e the scan's whitened residual (WallLineCost),
// s = |e|² and ρ(s) = s for s <= k², 2k√s − k² beyond (ρ′ = k/√s there), a scan in the linear
// region returns √ρ′ e and √ρ′ J: the rows of Ceres's loss correction (Triggs et al. 1999,
// Sec. 4.3; α = 0 since ρ″ <= 0), which give the exact gradient ρ′ Jᵀe of ½ρ(s). One more
// residual per block, √Σ(ρ − ρ′ s) over those scans with a zero Jacobian row, makes ½ of the
// block's sum of squares ½Σρ(s): the objective, for the steps' acceptance. The normal matrix
// of the block is then Σρ′ JᵀJ, the information the covariance and the checks use.
//
// The compressed form. The standing scans of one station in one slice share the heading (the
// dwell's), its drift time and the wall, and do not move: their rows differ only in the
// wall-angle entry of the rho row (the scanner's position along the wall). All their rows then
// lie in a 3-dimensional space, B = [P; T; u] (the first scan's two rows and the wall-angle
// unit row), and the block's stacked Jacobian is C B with C (2n x 3). With [C | r] = Q R (QR,
// by Givens rotations, one row at a time), the block returns four residuals instead of 2n + 1:
// the rows R_C B with residuals Qᵀr, and one residual with a zero row holding |r|² − |Qᵀr|² and
// the loss's top-up. JᵀJ, the gradient Jᵀr, the cost and the Gauss–Newton model are those of
// the rows per scan (up to rounding): Ceres takes the same steps, on a Jacobian a tenth the size.
//
// An observation of weight w (WallLineMeasurement::weight: it stands for w scans, its W carries
// √w) costs w·ρ(s/w), w scans' worth of the loss, each scan's s taken unweighted: ρ′ at s/w
// scales its rows and w(ρ − ρ′ s/w) enters the top-up. (ρ(w s) instead would put nearly every
// observation of a re-solve thinned 90-fold beyond the loss's corner: an L1 fit, less efficient
// than the full solve it stands for, and slow to converge.)

#include <ceres/cost_function.h>

#include <vector>

#include "solvers/wall_line_cost.h"

namespace wallcal::solvers {

class WallSliceCost : public ceres::CostFunction {
 public:
  // The observations measurements[indices[0]], measurements[indices[1]], ... (the vector is
  // kept alive and unmoved by the caller); huber_scale 0: no robust loss.
  WallSliceCost(const std::vector<WallLineMeasurement>& measurements, std::vector<int> indices,
                double huber_scale);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Whether the block returns the compressed form (below) rather than rows per scan.
  bool compressed() const { return compressed_; }
  static constexpr int kCompressedResiduals = 4;

 private:
  bool EvaluateCompressed(double const* const* parameters, double* residuals,
                          double** jacobians) const;

  const std::vector<WallLineMeasurement>& measurements_;
  std::vector<int> indices_;
  double huber_scale_;
  bool compressed_ = false;
};

}  // namespace wallcal::solvers
