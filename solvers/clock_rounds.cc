// SPDX-License-Identifier: Apache-2.0
#include "solvers/clock_rounds.h"

#include <algorithm>
#include <cmath>

namespace wallcal::solvers {

double PredictedRoundChange(double left_s, double previous_left_s) {
  if (!std::isfinite(previous_left_s) || previous_left_s == 0.0) return left_s;
  // The linear model's error over a shift is linear in it (a smoothed yaw rate) or quadratic
  // (where the path curves), so the last round's ratio would do for a smaller shift; but one
  // round measures it roughly (each solve re-weights the scans through the robust loss, and the
  // heading and position shifts mix), so it is taken twice: on continuous driving (bench (d3))
  // the ratio alone stopped a round early, 0.4 σ short in dt and 0.5 σ in δh.
  const double contraction = std::min(1.0, 2.0 * std::abs(left_s / previous_left_s));
  return contraction * left_s;
}

bool WorthARound(const ClockRoundRule& rule, double change_s, double sigma_s) {
  return std::abs(change_s) > std::max(rule.tolerance_s, rule.sigma_fraction * sigma_s);
}

}  // namespace wallcal::solvers
