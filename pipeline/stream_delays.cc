#include "pipeline/stream_delays.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace wallcal::pipeline {

const char* DelayStatusName(DelayStatus status) {
  switch (status) {
    case DelayStatus::kNotEstimated: return "not estimated";
    case DelayStatus::kNotDetermined: return "not determined (marginalised under its prior)";
    case DelayStatus::kDetermined: return "determined";
  }
  return "?";
}

// The σ (s) a delay would have from the data with the other delay left free, and its own
// prior. The time block's marginal information is the data's plus the two priors' (they act on
// these two parameters alone); the other delay's prior is taken out and the other delay
// eliminated. On drives along one wall the data hold only the sum of the two: the joint σ of
// each then borrows the other's prior through the sum, this one does not. `index`: 0 the clock
// offset, 1 the heading delay; priors in s (a heading delay that is not estimated: prior 0).
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

// A delay is determined when the data, with the other delay free, shrink its prior σ to less
// than half (DelayOwnSigma); its reported σ is the joint one.
StreamDelay ClassifyDelay(bool estimated, double value_s, double sigma_s, double prior_sigma_s,
                          double own_sigma_s) {
  StreamDelay delay;
  delay.prior_sigma_s = prior_sigma_s;
  if (!estimated) return delay;
  delay.value_s = value_s;
  delay.sigma_s = sigma_s;
  delay.status = own_sigma_s > 0.0 && own_sigma_s < 0.5 * prior_sigma_s
                     ? DelayStatus::kDetermined
                     : DelayStatus::kNotDetermined;
  return delay;
}

}  // namespace wallcal::pipeline
