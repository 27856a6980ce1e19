// SPDX-License-Identifier: Apache-2.0
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

StreamDelay ClassifyDelay(bool estimated, double value_s, double sigma_s, double prior_sigma_s,
                          bool determined) {
  StreamDelay delay;
  delay.prior_sigma_s = prior_sigma_s;
  if (!estimated) return delay;
  delay.value_s = value_s;
  delay.sigma_s = sigma_s;
  delay.status = determined ? DelayStatus::kDetermined : DelayStatus::kNotDetermined;
  return delay;
}

}  // namespace wallcal::pipeline
