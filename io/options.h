#pragma once
// Option structs for calibrate and simulate. Defaults live at the declaration; configs/ ships
// the same defaults as YAML. Validate() throws io::InputError naming the first bad field.
// Angles are radians here; the YAML files give them in degrees (keys ending in _deg).

#include <cmath>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// Wall detection in one scan (calib/wall_detector).
// What Validate() throws: an InputError that also carries the YAML key at fault
// ("detector.hough_rho_step_m"), so the reader of the file can add the key's line.
class OptionError : public InputError {
 public:
  OptionError(std::string key, const std::string& message)
      : InputError(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Largest Hough accumulator (theta rows x rho columns) the detector options may ask for: 2e7
// cells (80 MB of counters). The defaults need about 1e5.
inline constexpr double kMaxHoughCells = 2e7;

struct DetectorOptions {
  double hough_rho_step_m = 0.02;         // accumulator cell size in distance
  double hough_theta_step_rad = 0.0043633231;  // 0.25 deg
  int min_inliers = 15;                   // fewer points on the line: no detection
  double inlier_band_m = 0.08;            // Hough band kept for the least-squares refinement
  double refine_sigma_factor = 3.0;       // final inliers: |residual| < factor * preset σ + res.
  double mixed_pixel_jump_m = 0.15;       // a range jump this big marks both neighbours suspect
  double min_range_m = 0.5;               // closer points are ignored (vehicle body, mud)
  // Gates around the line predicted from the surveyed wall and the pose:
  double wide_angle_gate_rad = 0.34906585;   // first pass (mount known only roughly), 20 deg
  double wide_offset_gate_m = 6.0;     // first pass distance gate
  double tight_angle_gate_rad = 0.034906585; // second pass (mount from the first solve), 2 deg
  double tight_offset_gate_m = 0.25;   // second pass distance gate
  // Second pass: fewest inliers on the line (a tight gate on a surveyed wall leaves little but
  // the wall; a short stretch of a second wall at the edge of the view still counts). On the
  // two-wall benchmark the lines of 5-14 beams take the bound on x from 8.62 to 7.72 mm.
  int tight_min_inliers = 5;
  double wall_extent_margin_m = 0.5;   // inliers must project onto the surveyed wall ± this
  void Validate() const;
};

// Pose interpolation at scan times (calib/time_alignment).
struct AlignmentOptions {
  double max_gap_periods = 3.0;  // a gap longer than this many median sample periods: no pose
  double stationary_speed_mps = 0.05;      // slower than this (over the window) is a dwell
  double stationary_yaw_rate_rps = 0.005;  // and turning slower than this
  double stationary_window_s = 1.0;        // window for speed / yaw rate
  double min_dwell_s = 2.0;                // shorter dwells are not stations
  // Time cut off each end of a detected dwell. The edge test lets in samples up to the
  // stationary thresholds away from the stop's mean pose (a vehicle still finishing its turn,
  // 0.2° off in the simulator); a scan there, solved with the dwell's mean heading, is wrong by
  // that much, always with the sign of the turn. Measured on the two-wall benchmark: a −4.7 mm
  // x bias without the guard (docs/results.md).
  double dwell_guard_s = 0.2;
  bool use_moving_scans = false;           // scans taken while moving are skipped by default
  // Length of the GNSS-error slices (one 2-D RTK bias each, chained by the Gauss–Markov prior),
  // in dwells and in moving data. The RTK error wanders within a slice; keep it well below the
  // correlation time τ (about τ/240): with 5 s slices at τ = 60 s the simulated benchmark's y
  // error was 1.65× the Cramér–Rao bound, with 0.25 s it and its σ are at the bound
  // (docs/results.md). calibrate warns above τ/60.
  double segment_max_s = 0.25;
  // Use moving scans anyway when the session has fewer dwells than solver.min_stations (an
  // engineer drove continuously): the solver then also estimates the scanner clock offset.
  bool moving_scans_if_few_stations = true;
  // Put each GGA at its epoch mapped onto the logger clock (calib/gnss_epoch_time.h) when the
  // log has logger stamps and the sentences' UTC; false: at its arrival stamp.
  bool gnss_epoch_time = true;
  // Stop-and-go sessions: the scans taken while driving between the stops are used too, each
  // with its pose uncertainty (solver.moving_timing_sigma_s, interpolation, scans per GNSS fix)
  // in its covariance, when the timing their poses need is determined (the clock offset, or
  // offset + heading delay when turning: solvers::DrivesTimingSigma <=
  // moving_max_time_offset_sigma_s); otherwise they are dropped again and the standing scans
  // solved alone. false: standing scans only (unless use_moving_scans or too few stations).
  bool moving_scans_in_stop_and_go = true;
  double moving_max_time_offset_sigma_s = 0.005;
  void Validate() const;
};

// The mount solve (solvers/).
struct SolverOptions {
  // Noise model. σ values are 1-σ.
  double gnss_white_sigma_m = 0.005;      // per-epoch scatter of RTK positions
  double gnss_bias_sigma_m = 0.015;       // time-correlated RTK error, one per segment/station
  bool use_gst_sigma = true;              // take the bias σ from GST when the log has it
  double heading_sigma_rad = 0.0017453293;     // heading white noise, 0.1 deg
  double control_sigma_m = 0.015;         // RTK error of each control point
  double total_station_sigma_m = 0.003;   // total station point error (Barawid 2007: ±3 mm fine)
  double rotation_sigma_rad = 0.0034906585;    // σ of survey.rotation_deg (one control point), 0.2 deg
  double huber_scale = 2.0;               // robust loss threshold, in units of σ
  int max_iterations = 100;
  // Threads of the Ceres solve and of the information matrix. Not a YAML key: set from
  // calibrate's --threads (results agree to round-off whatever the count).
  int num_threads = 1;
  double min_heading_spread_rad = 0.34906585;   // 20 deg: narrower and the mount is not determined
  int min_observations = 30;
  int min_stations = 3;
  // Correlation time of the receiver's RTK error (first-order Gauss–Markov): the biases of
  // stations closer in time than this are correlated, so they count as fewer independent
  // realisations. 0: every segment's bias is independent.
  double gnss_bias_tau_s = 60.0;
  // Prior σ of the scanner-clock offset to the GNSS/heading clocks, estimated when moving scans
  // are used (0: never estimated).
  double time_offset_sigma_s = 0.1;
  // Prior σ of the heading stream's delay relative to the GNSS epochs (s; true yaw at a moving
  // scan = interpolated yaw + ω·(dt + δ_h)), estimated beside the clock offset from the turns
  // of the moving scans (0: held at 0). Not determined by the data (no turns): marginalised
  // under this prior, so the mount's σ carries it (docs/time-alignment.md).
  double heading_delay_sigma_s = 0.05;
  // A moving scan's pose timing uncertainty that no parameter takes up (s, 1σ, white per scan):
  // stamp jitter of the scanner and of the GNSS / heading sentences, the spread of their delays
  // about the estimated offset. Moves the pose by speed × σ along the track and the yaw by yaw
  // rate × σ (solvers/mount_problem.cc, MovingPoseCovariance).
  double moving_timing_sigma_s = 0.002;
  // Prior σ of the heading sensor's drift rate (rad/s; a FOG drifts linearly, Barawid 2007: ±0.5°/h),
  // estimated as one rate over the session (0: no drift modelled).
  double heading_drift_sigma_rad_per_s = 2.4240684e-6;  // 0.5 deg/h
  // Largest 1σ accepted for the mount: beyond these (in any combination of x, y, yaw) the mount
  // is "not determined" and calibrate refuses unless forced.
  double max_sigma_xy_m = 0.05;
  double max_sigma_yaw_rad = 0.0087266463;  // 0.5 deg
  // Repeatability: resamples of the stations (with replacement) re-solved; 0 switches it off.
  int bootstrap_samples = 50;
  void Validate() const;
};

// The verdict's tolerances (`acceptance:`): a usable mount within all of them is ACCEPT; a σ
// beyond them is REJECT; a change since the previous calibration (--compare) beyond them is
// REVIEW (the scanner may have been moved or bumped: a person decides). pipeline/verdict.h.
struct AcceptanceOptions {
  double max_sigma_xy_m = 0.02;             // 1σ of x and of y
  double max_sigma_yaw_rad = 0.0034906585;  // 1σ of yaw, 0.2 deg
  double max_change_xy_m = 0.02;            // |Δx|, |Δy| since the previous calibration
  double max_change_yaw_rad = 0.0052359878;  // |Δyaw|, 0.3 deg
  // A change is also REVIEW when it exceeds this many combined σ (σ_now² + σ_previous²)^½:
  // larger than the two calibrations' errors explain.
  double max_change_sigmas = 3.0;
  void Validate() const;
};

struct CalibrateOptions {
  DetectorOptions detector;
  AlignmentOptions alignment;
  SolverOptions solver;
  AcceptanceOptions acceptance;
  int first_pass_max_scans = 3000;  // scans sampled evenly for the first (wide-gate) pass
  void Validate() const;
};

// ---- Simulation -----------------------------------------------------------------------------

// A straight wall in the simulated site's local ground frame (east, north, metres).
struct SimWall {
  std::string id;
  std::string code;        // survey code; empty: not surveyed (a distractor wall)
  double x0_m = 0.0, y0_m = 0.0;  // one end, local east/north
  double x1_m = 0.0, y1_m = 0.0;  // other end
  double height_m = 3.0;
  double survey_spacing_m = 1.0;  // total-station point spacing along the wall
};

// A round obstacle (tree trunk, person) in the local ground frame.
struct SimObstacle {
  double x_m = 0.0, y_m = 0.0;
  double radius_m = 0.2;
};

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
  // True mount (vehicle frame: x forward, y left)
  double mount_x_m = 2.57;
  double mount_y_m = 0.056;
  double mount_yaw_rad = 0.048869;  // 2.8 deg
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
  // (sideways, along the wall), as before. Written to truth.yaml only when set.
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
  // Survey
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
  // ---- Per-stream logging delays (issue 16). The logger stamps each record when it receives
  // it: a GGA/GST `gnss_latency_s` + U(0, gnss_jitter_s) after its epoch (the sentence keeps
  // the epoch's UTC), an HDT `heading_latency_s` after its sample, a scan `scanner_latency_s`
  // after it was taken (on top of scanner_time_offset_s). 0: stamped at the epoch, as before.
  double gnss_latency_s = 0.0;
  double gnss_jitter_s = 0.0;
  double heading_latency_s = 0.0;
  double scanner_latency_s = 0.0;
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
  // > 0: the stations' antenna distances spread from station_distance_m to this (metres), in a
  // shuffled order so that distance and heading are not tied; 0: all at station_distance_m.
  double station_distance_far_m = 0.0;
  bool HasScannerTruth() const {
    return !std::isnan(truth_scale_n) || !std::isnan(truth_offset_c_m) ||
           !std::isnan(truth_sigma_m) || !std::isnan(truth_resolution_m) ||
           !std::isnan(truth_max_incidence_rad) || truth_drift_amplitude_m != 0.0 ||
           truth_drift_time_constant_s != 0.0;
  }
  void Validate() const;
};

}  // namespace wallcal::io
