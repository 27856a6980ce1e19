// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a stop the crew has not made yet would add: the wall observations a station at a given
// vehicle-to-wall angle, antenna distance and dwell would give, built under calibrate's own
// model so that solvers/ can weigh them with the stations already recorded. Each synthetic
// observation is the noise-free wall line (ρ, θ) the scanner would see from that pose, with the
// line fit's covariance of the beams that would fall on the wall, and stands for every scan of
// one GNSS-error slice (its weight): the slice's scans share every parameter block, so one row
// pair of weight k carries the information of k identical ones.

#include <array>
#include <vector>

#include "calib/observation.h"
#include "io/types.h"
#include "solvers/solver_options.h"

namespace wallcal::guide {

// One stop: which wall, the vehicle-to-wall angle φ (Barawid et al. 2007 Eq. 8: the wall's
// normal towards the wall in the vehicle frame, rad, ccw from vehicle x), the antenna's distance
// from the wall (m), how long to stand (s) and how long after the previous stop (or now) to
// start standing (s, the drive included).
struct StopSpec {
  int wall_index = 0;
  double vehicle_to_wall_rad = 0.0;
  double distance_m = 8.0;
  double dwell_s = 30.0;
  double wait_s = 30.0;
};

// A vehicle pose on the site: the antenna in the local frame (m) and the vehicle's yaw (rad, its
// x axis ccw from grid east, as calib::VehiclePose::yaw_rad).
struct SitePose {
  Eigen::Vector2d antenna_local_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
};

// What a synthetic stop needs from the session (or, for a plan, from the survey and preset).
struct StopModel {
  std::vector<calib::WallGeometry> walls;
  io::ScannerPreset preset;
  solvers::SolverOptions solver;
  calib::Mount mount;  // the current estimate, or scanner.mount_guess
  // Per wall: +1 when the vehicle stands where n·p < d (the side calibrate's stations were on).
  std::vector<double> side;
  double typical_distance_m = 8.0;  // the antenna's distance from the wall at the stations
  double scan_rate_hz = 0.0;     // scans logged per second (0: the preset's rate)
  double heading_rate_hz = 20.0;  // heading samples per second averaged over a dwell
  double gnss_sigma_m = 0.0;      // GST σ of the fixes (0: unknown, the solver's default)
  double gnss_period_s = 0.1;
  // The line fits' σ over the beam model's (ρ, θ), measured on the recorded observations (1
  // when there are none).
  double fit_scale = 1.0;
  // The adjustment where it ended (the wall corrections and the heading drift), so that a
  // synthetic observation has no residual under the robust loss: it is what the solution
  // predicts.
  std::vector<std::array<double, 2>> wall_deltas;
  double heading_drift_rad_per_s = 0.0;
  double heading_reference_s = 0.0;
  // The GNSS-error slices' time grid (start and length) and the first station id free.
  double slice_start_s = 0.0;
  double slice_s = 0.25;       // alignment.segment_max_s
  double dwell_guard_s = 0.2;  // alignment.dwell_guard_s: cut from both ends of a dwell
  int next_station_id = 0;
  // What the site adds to every prediction (x, y, yaw: m², m·rad, rad²): the mount's site terms
  // at the current solution (the scanner's height and tilt, the yard's grade, the walls' leans;
  // pipeline's SolveResult::site_terms), systematic: more stops do not reduce them.
  Eigen::Matrix3d site_covariance = Eigen::Matrix3d::Zero();
};

// The line fit a scanner at (rho_m, theta_rad) from the wall would make: the beams of the preset
// that hit the surveyed extent within range and incidence, their along-wall places and the
// (ρ, θ) covariance of a least-squares line through them (each point's σ the preset's range σ
// along its beam). False when fewer than 5 beams hit the wall.
struct LineFitModel {
  int beams = 0;
  double sigma_rho_m = 0.0;
  double sigma_theta_rad = 0.0;
  double cov_rho_theta = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
};
bool ModelLineFit(const StopModel& model, const calib::WallGeometry& wall,
                  const Eigen::Vector2d& scanner_local_m, double scanner_yaw_rad,
                  LineFitModel* fit);

// Where the model puts `stop`: the vehicle at stop.vehicle_to_wall_rad to its wall (on the side
// model.side says), the antenna stop.distance_m from the wall, and the scanner (at model.mount)
// abreast of the middle of the wall's surveyed extent. False when stop.wall_index is not a wall.
bool StopPose(const StopModel& model, const StopSpec& stop, SitePose* pose);

// The observations of `stop` standing from start_s to start_s + dwell_s, appended to
// *observations with their weights (scans per slice). False (nothing appended) when the wall
// would not be seen from there.
bool AppendStopObservations(const StopModel& model, const StopSpec& stop, double start_s,
                            int station_id, std::vector<calib::WallObservation>* observations,
                            std::vector<double>* weights);

// The drive from one stop to the next (s). A wait longer than this is spent standing on at the
// previous stop, as a stop-and-go crew does (the scanner keeps logging there).
inline constexpr double kDriveS = 5.0;

// `stop`, `wait_s` after wait_start_s, with the wait beyond kDriveS standing at `previous` (null:
// no previous stop, the wait adds nothing). Each standing gets the next station id from
// *next_station_id. False when the stop's wall would not be seen (nothing of it appended).
bool AppendWaitAndStop(const StopModel& model, const StopSpec* previous, const StopSpec& stop,
                       double wait_start_s, int* next_station_id,
                       std::vector<calib::WallObservation>* observations,
                       std::vector<double>* weights);

}  // namespace wallcal::guide
