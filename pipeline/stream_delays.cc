#include "pipeline/stream_delays.h"

namespace wallcal::pipeline {

const char* DelayStatusName(DelayStatus status) {
  switch (status) {
    case DelayStatus::kNotEstimated: return "not estimated";
    case DelayStatus::kNotDetermined: return "not determined (marginalised under its prior)";
    case DelayStatus::kDetermined: return "determined";
  }
  return "?";
}

// A delay is determined when the data, with the other delay free, shrink its prior σ to less
// than half (solvers::DelayOwnSigma); its reported σ is the joint one.
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
