// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one fixture of synthetic wall observations shared by the solver tests and the benchmarks:
// stations in front of a surveyed wall (y = 10 m, x from −10 to 10; optionally a second wall
// along x = 12 m), the antenna 7.5–8.5 m from it, headings spread evenly over a base ± half a
// spread, positions along the wall in a shuffled order; per scan the wall line (ρ, θ) the
// scanner sees from the true pose, with every error source of the adjustment drawn from its
// σ: the line fit, the GNSS (white and one bias per station, optionally Gauss–Markov in time),
// the heading, the survey of the walls, outliers, and for moving data the speed, turn rate and
// a scanner clock offset. Observations are built directly, without scans or the detector (the
// full simulator is sim/simulator.h).

#include <random>
#include <vector>

#include "calib/observation.h"
#include "common/angles.h"

namespace wallcal::sim {

struct SimSettings {
  calib::Mount truth{2.57, 0.056, 2.8 * kDegToRad};  // Barawid 2007's result
  int stations = 10;
  int scans_per_station = 20;
  double base_heading_rad = 0.5 * kPi;  // facing the first wall (north)
  double heading_half_spread_rad = 35.0 * kDegToRad;
  bool second_wall = false;  // a wall perpendicular to the first, east of the stations
  bool first_wall = true;
  bool noise = true;
  double fit_sigma_rho_m = 0.003;
  double fit_sigma_theta_rad = 0.002;
  double gnss_white_sigma_m = 0.003;
  double gnss_bias_sigma_m = 0.015;  // one draw per station, shared by its scans
  double heading_sigma_rad = 0.0009;
  double wall_sigma_offset_m = 0.005;
  double wall_sigma_angle_rad = 0.001;
  double outlier_fraction = 0.0;  // share of observations whose rho is off by +0.5 m
  // Time between stations: 10 min by default, so that their GNSS errors are independent under
  // the solver's Gauss–Markov model (τ = 60 s).
  double station_spacing_s = 600.0;
  // > 0: the stations' GNSS biases follow a first-order Gauss–Markov process of this
  // correlation time (as a receiver's RTK error does) instead of being drawn independently.
  double bias_tau_s = 0.0;
  // Moving data: the vehicle drives at this speed along its heading and turns at this rate
  // while scanning; the scanner's stamps are `time_offset_s` early (true time = stamp + offset).
  double speed_mps = 0.0;
  double yaw_rate_rps = 0.0;
  double time_offset_s = 0.0;
  bool alternate_direction = false;  // odd stations drive backwards and turn the other way
  double scan_period_s = 0.1;  // time between a station's scans
  // > 0: the pose's dwell fields (dwell_yaw_rad, dwell_yaw_samples, dwell_mid_s) are filled as
  // the pose interpolator fills them: the mean of this many heading samples (each with
  // heading_sigma_rad) over the dwell. 0: left empty (the solver averages the scans' yaws).
  int dwell_heading_samples = 0;
};

struct SimData {
  std::vector<calib::WallGeometry> walls;  // as surveyed (nominal)
  std::vector<calib::WallObservation> observations;
  std::vector<bool> is_outlier;
};

// Draws one session from `settings` with `rng` (the draws follow a fixed order: the same seed
// gives the same observations).
SimData SimulateObservations(const SimSettings& settings, std::mt19937& rng);

}  // namespace wallcal::sim
