// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the data hold of the two timing unknowns of the adjustment: the scanner clock offset dt
// and the heading stream's delay δh after the GNSS epochs (wall_line_cost.h), from the solve's
// [dt, δh] covariance. Used by the clock rounds (solve_policy.h) to move only what the data
// determine, and by the pipeline to report each delay's status.

#include <Eigen/Core>

namespace wallcal::solvers {

// The σ (s) a delay would have from the data with the other delay left free, and its own prior.
// time_covariance: the solve's [dt, δh] covariance (s²); priors in s (heading_prior_s 0: the
// heading delay is not estimated, the block is dt alone); index 0 the clock offset, 1 the
// heading delay. The time block's marginal information is the data's plus the two priors' (they
// act on these two parameters alone); the other delay's prior is taken out and the other delay
// eliminated. On drives along one wall the data hold only the sum of the two: the joint σ of
// each then borrows the other's prior through the sum, this one does not.
double DelayOwnSigma(const Eigen::Matrix2d& time_covariance, double clock_prior_s,
                     double heading_prior_s, int index);

// The rule for "determined", for a delay or a sum of delays: the data shrink its prior σ
// (prior_sigma_s) to below half (sigma_s, what it has with the data).
inline bool ShrinksPriorByHalf(double sigma_s, double prior_sigma_s) {
  return sigma_s > 0.0 && sigma_s < 0.5 * prior_sigma_s;
}

// Whether the data determine that delay: ShrinksPriorByHalf of its DelayOwnSigma.
bool DelayDetermined(const Eigen::Matrix2d& time_covariance, double clock_prior_s,
                     double heading_prior_s, int index);

}  // namespace wallcal::solvers
