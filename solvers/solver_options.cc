// SPDX-License-Identifier: Apache-2.0
#include "solvers/solver_options.h"

namespace wallcal::solvers {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

void SolverOptions::Validate() const {
  CheckPositive("solver.gnss_white_sigma_m", gnss_white_sigma_m);
  CheckPositive("solver.gnss_bias_sigma_m", gnss_bias_sigma_m);
  CheckAnglePositive("solver.heading_sigma_deg", heading_sigma_rad, 90.0);
  CheckPositive("solver.control_sigma_m", control_sigma_m);
  CheckPositive("solver.total_station_sigma_m", total_station_sigma_m);
  CheckAnglePositive("solver.rotation_sigma_deg", rotation_sigma_rad, 90.0);
  CheckPositive("solver.huber_scale", huber_scale);
  CheckAtLeast("solver.max_iterations", max_iterations, 1);
  CheckRange("solver.min_heading_spread_deg", min_heading_spread_rad * kRadToDeg, 0.0, 360.0);
  CheckAtLeast("solver.min_observations", min_observations, 1);
  CheckAtLeast("solver.min_stations", min_stations, 1);
  CheckNonNegative("solver.gnss_bias_tau_s", gnss_bias_tau_s);
  CheckNonNegative("solver.time_offset_sigma_s", time_offset_sigma_s);
  CheckNonNegative("solver.heading_delay_sigma_s", heading_delay_sigma_s);
  CheckNonNegative("solver.moving_timing_sigma_s", moving_timing_sigma_s);
  CheckNonNegative("solver.heading_drift_sigma_deg_per_h", heading_drift_sigma_rad_per_s);
  CheckPositive("solver.max_sigma_xy_m", max_sigma_xy_m);
  CheckAnglePositive("solver.max_sigma_yaw_deg", max_sigma_yaw_rad, 180.0);
  CheckAtLeast("solver.bootstrap_samples", bootstrap_samples, 0);
}

}  // namespace wallcal::solvers
