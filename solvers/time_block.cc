// SPDX-License-Identifier: Apache-2.0
#include "solvers/time_block.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace wallcal::solvers {

double DelayOwnSigma(const Eigen::Matrix2d& time_covariance, double clock_prior_s,
                     double heading_prior_s, int index) {
  const double own_prior = index == 0 ? clock_prior_s : heading_prior_s;
  if (!(heading_prior_s > 0.0)) {  // the clock offset alone
    return std::sqrt(std::max(0.0, time_covariance(0, 0)));
  }
  const Eigen::Matrix2d information = time_covariance.inverse();
  const int other = 1 - index;
  const double other_prior = index == 0 ? heading_prior_s : clock_prior_s;
  const double other_data = information(other, other) - 1.0 / (other_prior * other_prior);
  double own = information(index, index);  // the data's, and the own prior's
  if (other_data > 0.0) own -= information(index, other) * information(index, other) / other_data;
  own = std::max(own, 1.0 / (own_prior * own_prior));
  return 1.0 / std::sqrt(own);
}

bool DelayDetermined(const Eigen::Matrix2d& time_covariance, double clock_prior_s,
                     double heading_prior_s, int index) {
  const double prior_s = index == 0 ? clock_prior_s : heading_prior_s;
  return ShrinksPriorByHalf(
      DelayOwnSigma(time_covariance, clock_prior_s, heading_prior_s, index), prior_s);
}

}  // namespace wallcal::solvers
