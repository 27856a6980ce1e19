// SPDX-License-Identifier: Apache-2.0
#pragma once
// Fixtures for tests on hand-made or synthetic wall observations (sim/synthetic_observations.h):
// the north wall the synthetic sessions face, and the solver told the noise they were drawn with.

#include <Eigen/Core>

#include "calib/observation.h"
#include "sim/synthetic_observations.h"
#include "solvers/solver_options.h"

namespace wallcal::testing_support {

// The wall y = 10 m of the local frame, normal north, x from −10 to 10 m.
inline calib::WallGeometry NorthWall() {
  calib::WallGeometry wall;
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-10.0, 10.0);
  wall.end_b_local = Eigen::Vector2d(10.0, 10.0);
  return wall;
}

// Stations where the vehicle creeps forward at 1 m/s and turns at 3°/s while scanning, with the
// scanner's stamps 80 ms early (40 scans each). The clock offset moves the scanner by 8 cm and
// 0.24°. Every other station drives backwards: forward motion alone would trade the offset for x.
inline sim::SimSettings MovingStations() {
  sim::SimSettings s;
  s.speed_mps = 1.0;
  s.yaw_rate_rps = 3.0 * kDegToRad;
  s.time_offset_s = 0.08;
  s.scans_per_station = 40;
  s.alternate_direction = true;
  return s;
}

// The solver's noise model matching a synthetic session's (GST σ not used).
inline solvers::SolverOptions OptionsFor(const sim::SimSettings& s) {
  solvers::SolverOptions options;
  options.gnss_white_sigma_m = s.gnss_white_sigma_m;
  options.gnss_bias_sigma_m = s.gnss_bias_sigma_m;
  options.use_gst_sigma = false;
  options.heading_sigma_rad = s.heading_sigma_rad;
  return options;
}

}  // namespace wallcal::testing_support
