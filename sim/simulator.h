// SPDX-License-Identifier: Apache-2.0
#pragma once
// Synthesises a wall-calibration session with known truth: scans, GNSS fixes, headings, a
// total-station survey and RTK control points, as a field crew would log them (Barawid 2007 set-up).
// Plain structs out; writing files is io/'s job (apps/simulate_command.cc).
//
// Frames and units:
// - Physics happens in the site's local ENU frame (GeographicLib::LocalCartesian at
//   site_lat/lon/height), in ground metres: x = TRUE east, y = TRUE north, z up from the site
//   origin. This is not the UTM grid; the tool's own geodesy (meridian convergence, point scale)
//   turns the lat/lon and true headings produced here into its map frame, as it must for field
//   data.
// - The site is three-dimensional (sim/site_geometry.h): a ground plane through the site origin,
//   graded yard_grade_pct % rising towards yard_grade_dir; the vehicle (x forward, y left, z up,
//   origin at the GNSS antenna) stands on it, its attitude Rz(yaw)·Ry(−pitch)·Rx(roll) (pitch
//   positive nose up, roll positive right side down) following the ground under its heading, the
//   antenna antenna_height_m from the ground along its normal. The scanner's origin is
//   antenna + R_v·(mount_x, mount_y, mount_z), its axes R_v·Rz(mount_yaw)·Ry(−scanner_pitch)·
//   Rx(scanner_roll); a beam is a ray in its x–y plane and meets the nearest of: the walls (from
//   the ground up to height_m, upright or leaning by lean_deg), the round obstacles (upright, no
//   top), the ground. The trajectory is planned in the horizontal: antenna_enu_m is the
//   antenna's horizontal place, its height follows the ground.
// - A configuration with none of the 3-D site's keys (SimulationConfig::IsThreeDSite) is the
//   2-D model: no ground, walls without foot or top, the antenna, the scanner plane and the
//   site origin in one horizontal plane, GGA heights the site's plus vertical noise.
// - Angles are radians; headings are TRUE headings, clockwise from true north, in [0, 2π).

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/simulation_config.h"
#include "sim/site_geometry.h"
#include "io/types.h"

namespace wallcal::sim {

// Receives each logged scan, in time order. The record is only valid during the call.
using ScanSink = std::function<void(const io::ScanRecord& scan)>;

// The true vehicle pose at one instant (true time t = stamp_s − start_time_s; stamp_s is on the
// logging clock, the clock of the GNSS and heading logs).
struct SimTruthPose {
  double stamp_s;
  Eigen::Vector2d antenna_enu_m;  // local ENU (true east, true north), ground metres
  double yaw_enu_rad;             // vehicle x axis, ccw from true east (not wrapped)
  bool stationary;                // inside a station dwell
  // The vehicle's attitude on the ground (site_geometry.h's convention) and the antenna's height
  // (m, ENU up from the site origin); all 0 in the 2-D model.
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double antenna_up_m = 0.0;
};

struct SimulatedSession {
  // GGA epochs at gnss_rate_hz: WGS84 lat/lon/ellipsoidal height of the noisy antenna position,
  // quality 4 (RTK fixed) or 5 (float periods), GST σ in sigma_lat_m/sigma_lon_m (NaN when the
  // config says write_gst: false). stamp_s on the logging clock. The height: in a 3-D site the
  // antenna's, off by a vertical Gauss–Markov bias and white noise gnss_vertical_factor times
  // the horizontal ones (each on a stream of its own); in the 2-D model the site's, off by white
  // noise twice the horizontal.
  std::vector<io::GnssFix> fixes;
  // Measured TRUE headings at heading_rate_hz (clockwise from true north, rad, [0, 2π)).
  std::vector<io::HeadingSample> headings;
  // Measured attitude (roll, pitch) at attitude_rate_hz from t = 0: the true attitude plus white
  // noise attitude_white_sigma_rad on each (a stream of its own), roll_sigma_rad and
  // pitch_sigma_rad that σ; stamped as the headings are (heading_latency_s after the sample: the
  // same GNSS/INS unit). Empty when attitude_rate_hz is 0.
  std::vector<io::AttitudeSample> attitudes;
  // Total-station points (its own right-handed frame, levelled: z is ENU up, ground metres,
  // noisy). Control points C1, C2 come first with code "CTRL" on the ground (z = 0 in the 2-D
  // model), then W001, W002, … on each surveyed wall (code = wall code): at every
  // survey_spacing_m along its foot, one point on its face at each of its survey_heights_m
  // above the foot (0.5 m and height − 0.5 m unless set), leaning with the wall
  // (WallFacePoint).
  // survey_mode rover: R001, R002, … likewise (at the foot unless survey_heights_m is set),
  // frame io::SurveyFrame::kGeodetic (lat_deg, lon_deg, z_m the ellipsoidal height), off by
  // rover_sigma_m per horizontal axis and twice that vertically; no control points.
  std::vector<io::SurveyPoint> survey;
  // RTK-measured WGS84 positions of the control points (noisy, control_sigma_m per axis).
  std::vector<io::ControlPoint> control;
  // The surveyed walls (config walls with a non-empty code), in config order.
  std::vector<io::WallSpec> walls;
  // The true pose every 0.1 s from t = 0 to the end of the run, for tests.
  std::vector<SimTruthPose> truth_poses;
  // scans_generated: every scan the scanner produced; of every log_every_n-th, scans_lost were
  // lost in transmission (lost_scan_fraction) and scans_written were passed to the sink.
  int64_t scans_generated = 0, scans_lost = 0, scans_written = 0;
  // Beams of the written scans that returned a range from the ground (a 3-D site's yard seen by
  // a scanner pitched down or a vehicle tilted towards it).
  int64_t ground_returns = 0;
};

// Runs the simulation. Deterministic for a given (config, preset, seed): every noise source
// draws from its own random stream, so changing one setting does not reshuffle the others.
// Scans are passed to `sink` in time order and not kept (an hour at 75 Hz is 270 000 scans);
// `sink` may be empty. Each scan is treated as instantaneous (no motion during the sweep).
// Trajectory: stop-and-go (num_stations dwells of dwell_s joined by smooth drives) or, with
// config.continuous, one smooth sweep through the same headings and positions with a forward /
// back weave of ±weave_amplitude_m along the wall normal (mean speed drive_speed_mps), never
// stopping (every truth pose has stationary == false).
// Throws io::InputError when the config or preset cannot be simulated (config.Validate()
// fails, no wall has a survey code, fewer than 3 stations, the scanner would stand at or behind
// the wall or the weave would take it there, a negative weave amplitude or duration, a preset
// without beams or rate).
SimulatedSession Simulate(const sim::SimulationConfig& config, const io::ScannerPreset& preset,
                          uint64_t seed, const ScanSink& sink);

// The run's length in seconds of true time (the stop-and-go plan, or continuous_duration_s /
// the stop-and-go plan's length in continuous mode). Throws io::InputError like Simulate when
// the trajectory cannot be planned.
double RunDurationS(const sim::SimulationConfig& config);

// The true poses Simulate moves the vehicle through, at true times t_s (seconds since the start
// of the run, clamped to [0, RunDurationS]); stamp_s = config.start_time_s + t; with the roll,
// pitch and antenna height of a 3-D site. For benchmarks and tests that need the truth at scan
// times. Throws like RunDurationS.
std::vector<SimTruthPose> TruePosesAt(const sim::SimulationConfig& config,
                                      const std::vector<double>& t_s);

// The scanner's true pose in ENU (origin and axes, site_geometry.h) with the vehicle at `pose`
// (its roll, pitch and antenna height used as they stand: take poses from TruePosesAt) and the
// mount of `config` (mount_x/y/z, mount_yaw, scanner_pitch/roll).
SimScannerPose TrueScannerPose(const sim::SimulationConfig& config, const SimTruthPose& pose);

// One beam of a noise-free scan: what the beam's centre ray meets first.
struct SimBeamHit {
  double bearing_rad = 0.0;     // in the scanner frame (ccw from its x axis)
  double range_m = 0.0;         // true 3-D distance to the surface met; 0 when none
  int wall_index = -1;          // into config.walls; -1 for an obstacle, the ground or nothing
  bool ground = false;          // the surface met is the ground (a 3-D site's yard)
  double cos_incidence = 0.0;   // |cos| of the incidence angle on that surface
  bool returned = false;        // within max range and max incidence: the scanner reports it
  // The footprint's edges (±0.4 step) hit two surfaces > 0.1 m apart in range: a depth jump, a
  // mixed-pixel risk (one wall seen obliquely is not one, nor is the ground).
  bool footprint_edge = false;
};

// Where the crew surveys a wall (m, ENU): every survey_spacing_m (1 m when unset) from its first
// end, the first end alone for a wall of zero length.
std::vector<Eigen::Vector2d> SurveyStationsAlong(const SimWall& wall);
// The heights above a wall's foot at which the crew measures its face at each station: the
// wall's own survey_heights_m, or by default 0.5 m and height − 0.5 m (total station), the foot
// (rover).
std::vector<double> SurveyHeightsM(const SimWall& wall, SurveyMode mode);

// The scanner the simulation measures with: `preset` with the scenario's scanner_truth
// overrides (SimulationConfig's characterisation block) applied, then the unit's own errors
// off the correction where set (range_scale_error e_k, range_offset_error_m e_b):
// sim_scale_n × (1 + e_k), sim_offset_c_m + e_b / range_scale_k. Simulate passes it the
// config with drawn errors resolved (UnitRangeErrors); this function draws nothing.
io::ScannerPreset TrueScannerPreset(const sim::SimulationConfig& config,
                                    const io::ScannerPreset& preset);
// `config` with its unit's range errors resolved: with draw_unit_range_models, each of
// range_scale_error and range_offset_error_m that is not set (NaN) drawn from N(0,
// preset.range_scale_sigma) and N(0, preset.range_offset_sigma_m) (clipped to the keys'
// ranges, ±0.5 and ±1 m), on the scanner's own stream (seed and scanner_noise_stream): the same
// for a seed, another for each scanner of a session. Both are drawn whichever is given, so
// giving one leaves the other's draw as it was. Without the switch: `config` unchanged.
sim::SimulationConfig UnitRangeErrors(const sim::SimulationConfig& config,
                                      const io::ScannerPreset& preset, uint64_t seed);
// The scenario's warm-up range drift at true time t_s after the start (m, added to every range).
double RangeDriftM(const sim::SimulationConfig& config, double t_s);

// The noise-free scan the scanner would take at `pose` (TrueScannerPose: in a 3-D site the
// beams are tilted with the vehicle and the scanner, walls have a foot and a top and the ground
// returns beams), beam by beam, occlusions included. Does not check `config` (call
// RunDurationS or Simulate for that).
std::vector<SimBeamHit> TrueBeamHits(const sim::SimulationConfig& config,
                                     const io::ScannerPreset& preset, const SimTruthPose& pose);

// `config` unchanged when it has walls; otherwise with one 30 m surveyed wall "north_wall"
// (code WALL1) 12 m north of the site origin, running east–west from x = −15 m to x = +15 m.
sim::SimulationConfig WithDefaultWalls(sim::SimulationConfig config);

}  // namespace wallcal::sim
