// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's settings (configs/simulate/*.yaml, and truth.yaml's `simulation:`): the site,
// the true mount, walls and clutter, the trajectory, the sensors' noise and delays. Defaults at
// the declaration; angles are radians here and degrees in the files (keys ending in _deg).

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/angles.h"
#include "io/config/options_map.h"
#include "io/types.h"

namespace wallcal::sim {

using io::kNaN;

// A straight wall in the simulated site's local ground frame (east, north, metres). In the 3-D
// site (SimulationConfig::IsThreeDSite, sim/site_geometry.h) it stands on the ground from its
// foot up to height_m (measured vertically) and may lean; in the 2-D model it has neither foot
// nor top.
struct SimWall {
  std::string id;
  std::string code;        // survey code; empty: not surveyed (a distractor wall)
  double x0_m = 0.0, y0_m = 0.0;  // one end, local east/north
  double x1_m = 0.0, y1_m = 0.0;  // other end
  double height_m = 3.0;
  double survey_spacing_m = 1.0;  // total-station point spacing along the wall
  // The wall's plane tilted from vertical about its base line (rad): positive, its top leans
  // towards the left of the direction from (x0, y0) to (x1, y1); a point of its face h above
  // the foot lies h·tan(lean) from the base line. NaN: not set (vertical; key lean_deg).
  double lean_rad = kNaN;
  // The heights above the wall's foot (m, each within [0, height_m]) at which the crew measures
  // points on its face at every survey station along it. Empty: 0.5 m and height_m − 0.5 m
  // with a total station, the foot (0 m) with a rover.
  std::vector<double> survey_heights_m;
  double LeanRad() const { return std::isnan(lean_rad) ? 0.0 : lean_rad; }
};

// A round obstacle (tree trunk, person) in the local ground frame.
struct SimObstacle {
  double x_m = 0.0, y_m = 0.0;
  double radius_m = 0.2;
};

// One stop of an explicit stop-and-go plan (SimulationConfig::stops): the vehicle turned to the
// vehicle-to-wall angle φ (the wall's normal towards the wall in the vehicle frame, Barawid et
// al. 2007 Eq. 8), its antenna distance_m from the wall, standing dwell_s, starting wait_s after
// the previous stop ended (ignored for the first). The wait is the drive (as long as the even
// plan's drives) and, beyond it, standing on at the previous stop.
struct SimStop {
  double vehicle_to_wall_rad = 0.0;
  double distance_m = 8.0;
  double dwell_s = 4.0;
  double wait_s = 0.0;
};

// One more scanner on the simulated vehicle (a session with `scanners:`): its id (the
// session's scanner id and frame), its true mount and its own clock (the keys as the
// one-scanner settings of SimulationConfig name them).
struct SimScanner {
  std::string id;
  double mount_x_m = 0.0;
  double mount_y_m = 0.0;
  double mount_yaw_rad = 0.0;
  double scanner_time_offset_s = 0.0;
  double scanner_latency_s = 0.0;
  // Its height relative to the antenna and its tilt (SimulationConfig mount_z_m,
  // scanner_pitch_rad, scanner_roll_rad); NaN: not set (0).
  double z_m = kNaN;
  double pitch_rad = kNaN;
  double roll_rad = kNaN;
  // This unit's range model off the preset's correction (SimulationConfig range_scale_error,
  // range_offset_error_m); NaN: not set (none, or drawn with draw_unit_range_models).
  double range_scale_error = kNaN;
  double range_offset_error_m = kNaN;
};

// How the simulated crew surveys the walls (SimulationConfig::survey_mode).
enum class SurveyMode { kTotalStation, kRover };

struct SimulationConfig {
  // Site
  double site_lat_deg = 43.07;
  double site_lon_deg = 141.34;
  double site_height_m = 70.0;
  std::string name = "simulated";
  // Scanner
  std::string scanner_model = "sick_lms291";
  double log_every_n = 1;  // log every n-th scan (>= 1)
  double scanner_time_offset_s = 0.0;  // true offset: logged scan time = true time - this
  // True mount (vehicle frame: x forward, y left, z up)
  double mount_x_m = 2.57;
  double mount_y_m = 0.056;
  double mount_yaw_rad = 0.048869;  // 2.8 deg
  // ---- The 3-D site (sim/site_geometry.h). Any of these keys set (IsThreeDSite) makes the
  // site three-dimensional: a ground plane through the site origin at site_height_m, graded
  // yard_grade_pct % rising towards yard_grade_dir_rad; the vehicle standing on it (its roll and
  // pitch follow the ground under its heading) with the antenna antenna_height_m above it along
  // its normal; walls from the ground up to their height_m; a GGA height that is the antenna's,
  // off by vertical RTK noise gnss_vertical_factor times the horizontal. None set: the 2-D
  // model (no ground, antenna and scanner plane at the site origin's height). Each is written to
  // truth.yaml only when set. NaN: not set (the value in brackets).
  double yard_grade_pct = 0.0;        // rise per 100 m along the steepest direction (>= 0)
  double yard_grade_dir_rad = 0.0;    // where the ground rises towards: cw from true north
  double antenna_height_m = kNaN;     // [3.0] antenna above the ground, along its normal
  double gnss_vertical_factor = kNaN;  // [2.0] vertical RTK noise / horizontal, white and bias
  // The scanner's origin relative to the antenna along the vehicle's z axis (m, negative below
  // it) [0]; its tilt on the vehicle: scanner frame = R_v·Rz(mount_yaw)·Ry(−pitch)·Rx(roll),
  // pitch positive nose up, roll positive right side down.
  double mount_z_m = kNaN;
  double scanner_pitch_rad = 0.0;
  double scanner_roll_rad = 0.0;
  // What the crew writes into session.yaml: scanner.z_m when write_z_m and mount_z_m is set
  // (each scanner's z_m likewise); scanner.pitch_deg/roll_deg when write_tilt (the crew does
  // not always know the tilt).
  bool write_z_m = true;
  bool write_tilt = false;
  // Walls and clutter (local east/north metres relative to the site origin)
  std::vector<SimWall> walls;
  std::vector<SimObstacle> obstacles;
  // Trajectory: stations in front of the first wall
  int num_stations = 10;
  double station_distance_m = 8.0;     // antenna distance from the wall at stations
  double heading_spread_rad = 1.22;    // headings spread over ±(spread/2) around facing the wall
  double dwell_s = 4.0;                // time stopped at each station
  double drive_speed_mps = 1.0;
  double lateral_spread_m = 6.0;       // station positions spread along the wall
  // > 0: each drive between two stations backs the vehicle out to a point this far (m) behind
  // the two stations' midpoint and drives it forward into the next station, along curves that
  // keep its velocity on its own axis: a car-like vehicle (a tractor cannot move sideways),
  // turning while it moves. 0: the drive moves it on the straight line between the stations
  // (sideways, along the wall). Written to truth.yaml only when set.
  double drive_reverse_m = 0.0;
  // Continuous driving (no stops): the vehicle sweeps the stations' headings and positions once,
  // smoothly, over continuous_duration_s (0: as long as the stop-and-go plan), while weaving
  // forward and back along the wall normal by ±weave_amplitude_m at a mean speed of
  // drive_speed_mps.
  bool continuous = false;
  double weave_amplitude_m = 1.0;
  // > 0: the weave is driven along the vehicle's own axis, forward and back on an arc that turns
  // its heading by this much at ±weave_amplitude_m (a car-like vehicle steering as it weaves:
  // 8° over 1 m at 0.8 m/s turns at up to 10°/s, the sweep adding its own). 0: the weave moves
  // the vehicle along the wall normal whatever its heading (sideways when it is turned), as
  // before. Written to truth.yaml only when set.
  double weave_turn_rad = 0.0;
  double continuous_duration_s = 0.0;
  // GNSS
  double gnss_rate_hz = 10.0;
  double gnss_bias_sigma_m = 0.015;    // time-correlated (Gauss-Markov) RTK error
  double gnss_bias_tau_s = 60.0;
  double gnss_white_sigma_m = 0.003;
  double float_fraction = 0.0;         // share of time in RTK float (quality 5, σ ×10)
  bool write_gst = true;
  // Heading
  double heading_rate_hz = 20.0;
  double heading_white_sigma_rad = 0.0009;  // 0.05 deg
  double heading_drift_rad_per_s = 2.42e-6;  // 0.5 deg/h (Barawid 2007 FOG)
  double heading_bias_rad = 0.0;             // constant heading-sensor zero offset
  // Attitude stream (the vehicle's roll and pitch), sampled at attitude_rate_hz (0: none), each
  // axis off by attitude_white_sigma_rad. Text sessions: $PASHR sentences (attitude_sentence
  // "pashr") or $PTNL,AVR ("avr"), in the heading log or, with attitude_own_log, in a log of
  // their own (attitude.nmea); recordings: a sensor_msgs/Imu topic. Written to truth.yaml only
  // when attitude_rate_hz is not 0.
  double attitude_rate_hz = 0.0;
  double attitude_white_sigma_rad = 0.1 * kDegToRad;
  std::string attitude_sentence = "pashr";
  bool attitude_own_log = false;
  // Survey. kTotalStation: a total-station survey in its own frame, tied by two RTK control
  // points (survey.csv, survey.control). kRover: the wall points measured by an RTK rover
  // straight in latitude, longitude and ellipsoidal height, each off by rover_sigma_m per
  // horizontal axis (2× vertically), no control points (survey.point_sigma_m carries the σ).
  SurveyMode survey_mode = SurveyMode::kTotalStation;
  double rover_sigma_m = 0.010;
  double total_station_sigma_m = 0.003;
  double control_sigma_m = 0.015;
  double survey_rotation_rad = 0.4;      // total station frame rotation vs local east
  double survey_origin_x_m = -3.0;       // total station frame origin in local east/north
  double survey_origin_y_m = 20.0;
  // Scanner effects
  double lost_scan_fraction = 0.0008;    // Ye & Borenstein 2002: ≤ 0.08 %
  double mixed_pixel_probability = 0.5;  // chance a beam at a depth jump returns a mixed range
  // Logging clock: UNIX seconds at the start of the run
  double start_time_s = 1747031522.0;
  // ---- Per-stream logging delays. The logger stamps each record when it receives
  // it: a GGA/GST `gnss_latency_s` + U(0, gnss_jitter_s) after its epoch (the sentence keeps
  // the epoch's UTC), an HDT `heading_latency_s` after its sample, a scan `scanner_latency_s`
  // after it was taken (on top of scanner_time_offset_s). 0: stamped at the epoch.
  double gnss_latency_s = 0.0;
  double gnss_jitter_s = 0.0;
  double heading_latency_s = 0.0;
  double scanner_latency_s = 0.0;
  // > 0: each written scan's stamp is a further U(0, scanner_jitter_s) late (the logger stamps
  // on arrival, as gnss_jitter_s), drawn per scanner on a stream of its own. Written to
  // truth.yaml only when set.
  double scanner_jitter_s = 0.0;
  // ---- Characterisation (characterise): the scanner's true range model and the stations'
  // distances. Not written to truth.yaml unless set, so older scenarios simulate unchanged.
  // scanner_truth: {n:, c_m:, sigma_m:, resolution_m:, max_incidence_deg:, drift: {amplitude_m:,
  // time_constant_s:}}; NaN: the preset's value (simulation.n, c_m, sigma_m, range_resolution_m,
  // max_incidence_deg). The logged range is z = Int(n·true + c + drift(t) + ξ) (Ye & Borenstein
  // 2002; Okubo, Ye & Borenstein 2009), drift(t) = amplitude·(1 − exp(−t/time_constant)), t from
  // the run's start: a warm-up (Okubo et al. 2009 saw the URG's ranges drift for hours).
  double truth_scale_n = kNaN;
  double truth_offset_c_m = kNaN;
  double truth_sigma_m = kNaN;
  double truth_resolution_m = kNaN;
  double truth_max_incidence_rad = kNaN;
  double truth_drift_amplitude_m = 0.0;
  double truth_drift_time_constant_s = 0.0;  // 0 with amplitude != 0: a step at t = 0
  // ---- The unit's own range model: how far this scanner unit is off the preset's correction
  // (corrected = k·raw + b). range_scale_error e_k (relative) and range_offset_error_m e_b
  // make the true model n' = n·(1 + e_k), c' = c + e_b / k (n, c after scanner_truth; k the
  // preset's range_scale_k), so that the tool's corrected range is off by e_k·k·n·y + e_b for
  // a true range y (k·n ≈ 1: a relative e_k). NaN: not set; with draw_unit_range_models, each
  // unit whose value is not set draws it: e_k ~ N(0, range_scale_sigma), e_b ~ N(0,
  // range_offset_sigma_m) of the preset (UnitRangeErrors, sim/simulator.h), on a stream of its
  // own per scanner, so that every other draw of the session stays as it was. With `scanners:`
  // each scanner carries its own (SimScanner), these two are not used. truth.yaml records the
  // values applied, drawn ones included, and draw_unit_range_models only when true.
  double range_scale_error = kNaN;
  double range_offset_error_m = kNaN;
  bool draw_unit_range_models = false;
  // > 0: the stations' antenna distances spread from station_distance_m to this (metres), in a
  // shuffled order so that distance and heading are not tied; 0: all at station_distance_m.
  double station_distance_far_m = 0.0;
  // Not empty: these stops instead of num_stations, station_distance_m, heading_spread_rad and
  // dwell_s (stop and go only; the lateral place follows the heading as in the even plan,
  // lateral_spread_m over heading_spread_rad). Set by programs (the guide's crew benchmark),
  // not read from a scenario file nor written to truth.yaml.
  std::vector<SimStop> stops;
  // Several scanners (written only when set): each with its own mount and clock; the session
  // then lists them under `scanners:` with one scan log (or topic) each, and the single
  // scanner's mount_* and delays above are not used. Empty: one scanner, as above.
  std::vector<SimScanner> scanners;
  // Which scanner's noise streams (range noise, mixed pixels, lost scans, the unit's range
  // model, stamp jitter) a run draws from:
  // 0 for the first (and only) scanner, k for the k-th of `scanners`, so that two scanners'
  // range noise is independent while the GNSS, heading and survey draws are shared. Set by the
  // session writer, not a key.
  uint32_t scanner_noise_stream = 0;
  // The site is three-dimensional: a key of the 3-D site above is set (a wall's lean_deg, a
  // scanner's z_m, pitch_deg or roll_deg count too). False: the 2-D model.
  bool IsThreeDSite() const;
  // The 3-D site's values, with their defaults where a key is not set.
  double AntennaHeightM() const { return std::isnan(antenna_height_m) ? 3.0 : antenna_height_m; }
  double GnssVerticalFactor() const {
    return std::isnan(gnss_vertical_factor) ? 2.0 : gnss_vertical_factor;
  }
  double MountZM() const { return std::isnan(mount_z_m) ? 0.0 : mount_z_m; }
  bool HasScannerTruth() const {
    return !std::isnan(truth_scale_n) || !std::isnan(truth_offset_c_m) ||
           !std::isnan(truth_sigma_m) || !std::isnan(truth_resolution_m) ||
           !std::isnan(truth_max_incidence_rad) || truth_drift_amplitude_m != 0.0 ||
           truth_drift_time_constant_s != 0.0;
  }
  void Validate() const;
};

// The keys every scenario and truth.yaml carry and their checks, for any visitor of
// io/config/options_map.h. The per-stream delays, the car-like drives, more scanners, the
// scanner's true range model and the 3-D site are read beside them (ReadSimulationConfig) and
// written only when set; so are a wall's lean_deg and survey_heights_m and a scanner's z_m,
// pitch_deg, roll_deg, range_scale_error and range_offset_error_m (unset, they are left out of
// its flow map).
template <class V>
void VisitSimWall(V& v, SimWall& w) {
  v.Text("id", w.id, io::NonEmpty());
  v.Text("code", w.code);
  v.Number("x0_m", w.x0_m, io::Finite());
  v.Number("y0_m", w.y0_m, io::Finite());
  v.Number("x1_m", w.x1_m, io::Finite());
  v.Number("y1_m", w.y1_m, io::Finite());
  v.Number("height_m", w.height_m, io::Positive());
  v.Number("survey_spacing_m", w.survey_spacing_m, io::Positive());
  v.Scaled("lean_deg", w.lean_rad, kRadToDeg, io::InRange(-30.0, 30.0).OrUnset());
  v.Numbers("survey_heights_m", w.survey_heights_m, io::NonNegative());
}

template <class V>
void VisitSimObstacle(V& v, SimObstacle& o) {
  v.Number("x_m", o.x_m, io::Finite());
  v.Number("y_m", o.y_m, io::Finite());
  v.Number("radius_m", o.radius_m, io::Positive());
}

template <class V>
void VisitSimScanner(V& v, SimScanner& s) {
  v.Text("id", s.id, io::NonEmpty());
  v.Number("mount_x_m", s.mount_x_m, io::Finite());
  v.Number("mount_y_m", s.mount_y_m, io::Finite());
  v.Scaled("mount_yaw_deg", s.mount_yaw_rad, kRadToDeg, io::InRange(-180.0, 180.0));
  v.Number("scanner_time_offset_s", s.scanner_time_offset_s, io::Finite());
  v.Number("scanner_latency_s", s.scanner_latency_s, io::InRange(0.0, 10.0));
  v.Number("z_m", s.z_m, io::InRange(-10.0, 10.0).OrUnset());
  v.Scaled("pitch_deg", s.pitch_rad, kRadToDeg, io::InRange(-45.0, 45.0).OrUnset());
  v.Scaled("roll_deg", s.roll_rad, kRadToDeg, io::InRange(-45.0, 45.0).OrUnset());
  v.Number("range_scale_error", s.range_scale_error, io::InRange(-0.5, 0.5).OrUnset());
  v.Number("range_offset_error_m", s.range_offset_error_m, io::InRange(-1.0, 1.0).OrUnset());
}

template <class V>
void VisitSimulationConfig(V& v, SimulationConfig& c) {
  v.Number("site_lat_deg", c.site_lat_deg, io::InRange(-80.0, 84.0));  // UTM's latitude band
  v.Number("site_lon_deg", c.site_lon_deg, io::InRange(-180.0, 180.0));
  v.Number("site_height_m", c.site_height_m, io::Finite());
  v.Text("name", c.name, io::NonEmpty());
  v.Text("scanner_model", c.scanner_model, io::NonEmpty());
  v.Number("log_every_n", c.log_every_n, io::AtLeast(1.0));
  v.Number("scanner_time_offset_s", c.scanner_time_offset_s, io::Finite());
  v.Number("mount_x_m", c.mount_x_m, io::Finite());
  v.Number("mount_y_m", c.mount_y_m, io::Finite());
  v.Scaled("mount_yaw_deg", c.mount_yaw_rad, kRadToDeg, io::InRange(-180.0, 180.0));
  v.List("walls", c.walls, [](V& item_v, SimWall& w) { VisitSimWall(item_v, w); });
  v.List("obstacles", c.obstacles, [](V& item_v, SimObstacle& o) { VisitSimObstacle(item_v, o); });
  v.Integer("num_stations", c.num_stations, io::AtLeast(1));
  v.Number("station_distance_m", c.station_distance_m, io::Positive());
  v.Scaled("heading_spread_deg", c.heading_spread_rad, kRadToDeg, io::InRange(0.0, 360.0));
  v.Number("dwell_s", c.dwell_s, io::NonNegative());
  v.Number("drive_speed_mps", c.drive_speed_mps, io::Positive());
  v.Number("lateral_spread_m", c.lateral_spread_m, io::NonNegative());
  v.Boolean("continuous", c.continuous);
  v.Number("weave_amplitude_m", c.weave_amplitude_m);
  v.Number("continuous_duration_s", c.continuous_duration_s);
  v.Number("gnss_rate_hz", c.gnss_rate_hz, io::Positive());
  v.Number("gnss_bias_sigma_m", c.gnss_bias_sigma_m, io::NonNegative());
  v.Number("gnss_bias_tau_s", c.gnss_bias_tau_s, io::Positive());
  v.Number("gnss_white_sigma_m", c.gnss_white_sigma_m, io::NonNegative());
  v.Number("float_fraction", c.float_fraction, io::InRange(0.0, 1.0));
  v.Boolean("write_gst", c.write_gst);
  v.Number("heading_rate_hz", c.heading_rate_hz, io::Positive());
  v.Scaled("heading_white_sigma_deg", c.heading_white_sigma_rad, kRadToDeg, io::NonNegative());
  v.Scaled("heading_drift_deg_per_h", c.heading_drift_rad_per_s, kDegPerHourPerRadPerS,
           io::Finite());
  v.Scaled("heading_bias_deg", c.heading_bias_rad, kRadToDeg, io::Finite());
  v.Number("total_station_sigma_m", c.total_station_sigma_m, io::NonNegative());
  v.Number("control_sigma_m", c.control_sigma_m, io::NonNegative());
  v.Scaled("survey_rotation_deg", c.survey_rotation_rad, kRadToDeg, io::Finite());
  v.Number("survey_origin_x_m", c.survey_origin_x_m, io::Finite());
  v.Number("survey_origin_y_m", c.survey_origin_y_m, io::Finite());
  v.Number("lost_scan_fraction", c.lost_scan_fraction, io::UpToBelow(0.0, 1.0));
  v.Number("mixed_pixel_probability", c.mixed_pixel_probability, io::InRange(0.0, 1.0));
  v.Number("start_time_s", c.start_time_s, io::NonNegative());
}

// A simulation configuration: the SimulationConfig keys at the top level, `walls:` a list of
// maps. Throws io::InputError "file:line: ..." for a bad or unknown key.
SimulationConfig ReadSimulationConfig(const std::string& file);

// The one-scanner configuration of config.scanners[index]: its mount (height and tilt
// included) and clock in the single scanner's fields, its own noise streams
// (scanner_noise_stream = index), its own range_scale_error and range_offset_error_m (NaN
// when it has none), no list; a 3-D site stays 3-D (the antenna's height is set when only
// another scanner's keys made it so).
SimulationConfig ForScanner(const SimulationConfig& config, size_t index);

// truth.yaml as written by FormatTruthYaml: the settings under `simulation:`, the exact mount
// under `truth:`.
SimulationConfig ReadTruthYaml(const std::string& file);

// truth.yaml: `truth: {x, y, yaw, yaw_deg}` (the true mount; with z when mount_z_m is set,
// pitch_deg and roll_deg when the scanner is tilted), `seed:` and `simulation:` with every
// SimulationConfig key (names as in ReadSimulationConfig). ReadTruthYaml reads it back.
std::string FormatTruthYaml(const SimulationConfig& config, uint64_t seed);

}  // namespace wallcal::sim
