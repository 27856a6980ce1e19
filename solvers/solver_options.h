// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mount solve's noise model and limits (`solver:` in configs/calibrate.yaml), their YAML
// keys and the check of each. Angles are radians here and degrees in the file; σ values are 1σ.

#include "common/angles.h"
#include "calib/survey_tie.h"
#include "io/config/options_map.h"

namespace wallcal::solvers {

// The mount solve (solvers/).
struct SolverOptions {
  // Noise model. σ values are 1-σ.
  double gnss_white_sigma_m = 0.005;      // per-epoch scatter of RTK positions
  double gnss_bias_sigma_m = 0.015;       // time-correlated RTK error, one per segment/station
  bool use_gst_sigma = true;              // take the bias σ from GST when the log has it
  double heading_sigma_rad = 0.0017453293;     // heading white noise, 0.1 deg
  // Take the GNSS and heading white noise from the stops' own scatter when they hold enough
  // samples (calib/white_noise.h), else from the drives' (calib/drive_white_noise.h; calibrate
  // reports where each came from): gnss_white_sigma_m and heading_sigma_rad are the fallbacks.
  bool use_measured_white_noise = true;
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
  calib::SurveySigmas survey() const {
    return {control_sigma_m, total_station_sigma_m, rotation_sigma_rad};
  }
  void Validate() const;
};

// The `solver:` keys and their checks, for any visitor of io/config/options_map.h.
template <class V>
void VisitSolverOptions(V& v, SolverOptions& o) {
  v.Number("gnss_white_sigma_m", o.gnss_white_sigma_m, io::Positive());
  v.Number("gnss_bias_sigma_m", o.gnss_bias_sigma_m, io::Positive());
  v.Boolean("use_gst_sigma", o.use_gst_sigma);
  v.Scaled("heading_sigma_deg", o.heading_sigma_rad, kRadToDeg, io::AboveUpTo(0.0, 90.0));
  v.Boolean("use_measured_white_noise", o.use_measured_white_noise);
  v.Scaled("heading_drift_sigma_deg_per_h", o.heading_drift_sigma_rad_per_s,
           kDegPerHourPerRadPerS, io::NonNegative());
  v.Number("control_sigma_m", o.control_sigma_m, io::Positive());
  v.Number("total_station_sigma_m", o.total_station_sigma_m, io::Positive());
  v.Scaled("rotation_sigma_deg", o.rotation_sigma_rad, kRadToDeg, io::AboveUpTo(0.0, 90.0));
  v.Number("huber_scale", o.huber_scale, io::Positive());
  v.Integer("max_iterations", o.max_iterations, io::AtLeast(1));
  v.Scaled("min_heading_spread_deg", o.min_heading_spread_rad, kRadToDeg, io::InRange(0.0, 360.0));
  v.Integer("min_observations", o.min_observations, io::AtLeast(1));
  v.Integer("min_stations", o.min_stations, io::AtLeast(1));
  v.Number("gnss_bias_tau_s", o.gnss_bias_tau_s, io::NonNegative());
  v.Number("time_offset_sigma_s", o.time_offset_sigma_s, io::NonNegative());
  v.Number("heading_delay_sigma_s", o.heading_delay_sigma_s, io::NonNegative());
  v.Number("moving_timing_sigma_s", o.moving_timing_sigma_s, io::NonNegative());
  v.Number("max_sigma_xy_m", o.max_sigma_xy_m, io::Positive());
  v.Scaled("max_sigma_yaw_deg", o.max_sigma_yaw_rad, kRadToDeg, io::AboveUpTo(0.0, 180.0));
  v.Integer("bootstrap_samples", o.bootstrap_samples, io::AtLeast(0));
}

}  // namespace wallcal::solvers
