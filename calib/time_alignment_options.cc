// SPDX-License-Identifier: Apache-2.0
#include "calib/time_alignment_options.h"

#include <cmath>

namespace wallcal::calib {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

void AlignmentOptions::Validate() const {
  CheckPositive("alignment.max_gap_periods", max_gap_periods);
  CheckPositive("alignment.stationary_speed_mps", stationary_speed_mps);
  if (!(std::isfinite(stationary_yaw_rate_rps) && stationary_yaw_rate_rps > 0.0)) {
    Fail("alignment.stationary_yaw_rate_deg_per_s", "> 0",
         Number(stationary_yaw_rate_rps * kRadToDeg));
  }
  CheckPositive("alignment.stationary_window_s", stationary_window_s);
  CheckNonNegative("alignment.min_dwell_s", min_dwell_s);
  CheckNonNegative("alignment.dwell_guard_s", dwell_guard_s);
  CheckPositive("alignment.segment_max_s", segment_max_s);
  CheckNonNegative("alignment.moving_max_time_offset_sigma_s", moving_max_time_offset_sigma_s);
}

}  // namespace wallcal::calib
