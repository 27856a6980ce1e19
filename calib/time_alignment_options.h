// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pose interpolation and dwell detection options (`alignment:` in configs/calibrate.yaml), their
// YAML keys and the check of each. Angles are radians here and degrees in the file.

#include "common/angles.h"
#include "io/config/options_map.h"

namespace wallcal::calib {

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
  // The slices of the joint adjustment of several scanners, at most this long (each
  // segment_max_s slice split into equal parts, calib/gnss_slices.h). That adjustment carries
  // each GNSS fix's white noise as a parameter, so a scan's own noise there is its line fit's
  // alone (0.6–1.4 mm on a two-scanner stop-and-go benchmark session), and the RTK error's wander within a slice, σ_b √(Δ/3τ)
  // (0.56 mm at 0.25 s, 0.25 mm at 0.05 s for σ_b 15 mm, τ 60 s), must stay well below it: with
  // 0.25 s slices the two-scanner stop-and-go mounts' x was 1.16 × its bound with RMS(err/σ)
  // 1.23, with 0.05 s 1.04 and 1.01 (docs/results.md).
  double joint_segment_max_s = 0.05;
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

// The `alignment:` keys and their checks, for any visitor of io/config/options_map.h.
template <class V>
void VisitAlignmentOptions(V& v, AlignmentOptions& o) {
  v.Number("max_gap_periods", o.max_gap_periods, io::Positive());
  v.Number("stationary_speed_mps", o.stationary_speed_mps, io::Positive());
  v.Scaled("stationary_yaw_rate_deg_per_s", o.stationary_yaw_rate_rps, kRadToDeg, io::Positive());
  v.Number("stationary_window_s", o.stationary_window_s, io::Positive());
  v.Number("min_dwell_s", o.min_dwell_s, io::NonNegative());
  v.Number("dwell_guard_s", o.dwell_guard_s, io::NonNegative());
  v.Boolean("use_moving_scans", o.use_moving_scans);
  v.Number("segment_max_s", o.segment_max_s, io::Positive());
  v.Number("joint_segment_max_s", o.joint_segment_max_s, io::Positive());
  v.Boolean("moving_scans_if_few_stations", o.moving_scans_if_few_stations);
  v.Boolean("gnss_epoch_time", o.gnss_epoch_time);
  v.Boolean("moving_scans_in_stop_and_go", o.moving_scans_in_stop_and_go);
  v.Number("moving_max_time_offset_sigma_s", o.moving_max_time_offset_sigma_s, io::NonNegative());
}

}  // namespace wallcal::calib
