#pragma once
// Internal to io/: the one list of YAML keys of each option struct, shared by the readers
// (session_reader.cc) and the writers (writers.cc) so that what is written reads back.
//
// A visitor V provides:
//   v.Number(key, double&)                 the value as written
//   v.Scaled(key, double&, file_per_unit)  the file holds value * file_per_unit (degrees ...)
//   v.Integer(key, int&), v.Boolean(key, bool&), v.Text(key, std::string&)
//   v.List(key, std::vector<T>&, visit_item)  a list of maps, each visited by visit_item(v, T&)

#include "io/options.h"
#include "common/angles.h"

namespace wallcal::io::fields {

inline constexpr double kRadToDeg = 57.295779513082320876798;  // 180 / π
inline constexpr double kDegPerHourPerRadPerS = kRadToDeg * 3600.0;

template <class V>
void VisitDetector(V& v, DetectorOptions& o) {
  v.Number("hough_rho_step_m", o.hough_rho_step_m);
  v.Scaled("hough_theta_step_deg", o.hough_theta_step_rad, kRadToDeg);
  v.Integer("min_inliers", o.min_inliers);
  v.Number("inlier_band_m", o.inlier_band_m);
  v.Number("refine_sigma_factor", o.refine_sigma_factor);
  v.Number("mixed_pixel_jump_m", o.mixed_pixel_jump_m);
  v.Number("min_range_m", o.min_range_m);
  v.Scaled("wide_angle_gate_deg", o.wide_angle_gate_rad, kRadToDeg);
  v.Number("wide_offset_gate_m", o.wide_offset_gate_m);
  v.Scaled("tight_angle_gate_deg", o.tight_angle_gate_rad, kRadToDeg);
  v.Number("tight_offset_gate_m", o.tight_offset_gate_m);
  v.Integer("tight_min_inliers", o.tight_min_inliers);
  v.Number("wall_extent_margin_m", o.wall_extent_margin_m);
}

template <class V>
void VisitAlignment(V& v, AlignmentOptions& o) {
  v.Number("max_gap_periods", o.max_gap_periods);
  v.Number("stationary_speed_mps", o.stationary_speed_mps);
  v.Scaled("stationary_yaw_rate_deg_per_s", o.stationary_yaw_rate_rps, kRadToDeg);
  v.Number("stationary_window_s", o.stationary_window_s);
  v.Number("min_dwell_s", o.min_dwell_s);
  v.Number("dwell_guard_s", o.dwell_guard_s);
  v.Boolean("use_moving_scans", o.use_moving_scans);
  v.Number("segment_max_s", o.segment_max_s);
  v.Boolean("moving_scans_if_few_stations", o.moving_scans_if_few_stations);
  v.Boolean("gnss_epoch_time", o.gnss_epoch_time);
  v.Boolean("moving_scans_in_stop_and_go", o.moving_scans_in_stop_and_go);
  v.Number("moving_max_time_offset_sigma_s", o.moving_max_time_offset_sigma_s);
}

template <class V>
void VisitAcceptance(V& v, AcceptanceOptions& o) {
  v.Number("max_sigma_xy_m", o.max_sigma_xy_m);
  v.Scaled("max_sigma_yaw_deg", o.max_sigma_yaw_rad, kRadToDeg);
  v.Number("max_change_xy_m", o.max_change_xy_m);
  v.Scaled("max_change_yaw_deg", o.max_change_yaw_rad, kRadToDeg);
  v.Number("max_change_sigmas", o.max_change_sigmas);
}

template <class V>
void VisitSolver(V& v, SolverOptions& o) {
  v.Number("gnss_white_sigma_m", o.gnss_white_sigma_m);
  v.Number("gnss_bias_sigma_m", o.gnss_bias_sigma_m);
  v.Boolean("use_gst_sigma", o.use_gst_sigma);
  v.Scaled("heading_sigma_deg", o.heading_sigma_rad, kRadToDeg);
  v.Scaled("heading_drift_sigma_deg_per_h", o.heading_drift_sigma_rad_per_s,
           kDegPerHourPerRadPerS);
  v.Number("control_sigma_m", o.control_sigma_m);
  v.Number("total_station_sigma_m", o.total_station_sigma_m);
  v.Scaled("rotation_sigma_deg", o.rotation_sigma_rad, kRadToDeg);
  v.Number("huber_scale", o.huber_scale);
  v.Integer("max_iterations", o.max_iterations);
  v.Scaled("min_heading_spread_deg", o.min_heading_spread_rad, kRadToDeg);
  v.Integer("min_observations", o.min_observations);
  v.Integer("min_stations", o.min_stations);
  v.Number("gnss_bias_tau_s", o.gnss_bias_tau_s);
  v.Number("time_offset_sigma_s", o.time_offset_sigma_s);
  v.Number("heading_delay_sigma_s", o.heading_delay_sigma_s);
  v.Number("moving_timing_sigma_s", o.moving_timing_sigma_s);
  v.Number("max_sigma_xy_m", o.max_sigma_xy_m);
  v.Scaled("max_sigma_yaw_deg", o.max_sigma_yaw_rad, kRadToDeg);
  v.Integer("bootstrap_samples", o.bootstrap_samples);
}

template <class V>
void VisitSimWall(V& v, SimWall& w) {
  v.Text("id", w.id);
  v.Text("code", w.code);
  v.Number("x0_m", w.x0_m);
  v.Number("y0_m", w.y0_m);
  v.Number("x1_m", w.x1_m);
  v.Number("y1_m", w.y1_m);
  v.Number("height_m", w.height_m);
  v.Number("survey_spacing_m", w.survey_spacing_m);
}

template <class V>
void VisitSimObstacle(V& v, SimObstacle& o) {
  v.Number("x_m", o.x_m);
  v.Number("y_m", o.y_m);
  v.Number("radius_m", o.radius_m);
}

template <class V>
void VisitSimulation(V& v, SimulationConfig& c) {
  v.Number("site_lat_deg", c.site_lat_deg);
  v.Number("site_lon_deg", c.site_lon_deg);
  v.Number("site_height_m", c.site_height_m);
  v.Text("name", c.name);
  v.Text("scanner_model", c.scanner_model);
  v.Number("log_every_n", c.log_every_n);
  v.Number("scanner_time_offset_s", c.scanner_time_offset_s);
  v.Number("mount_x_m", c.mount_x_m);
  v.Number("mount_y_m", c.mount_y_m);
  v.Scaled("mount_yaw_deg", c.mount_yaw_rad, kRadToDeg);
  v.List("walls", c.walls, [](V& item_v, SimWall& w) { VisitSimWall(item_v, w); });
  v.List("obstacles", c.obstacles, [](V& item_v, SimObstacle& o) { VisitSimObstacle(item_v, o); });
  v.Integer("num_stations", c.num_stations);
  v.Number("station_distance_m", c.station_distance_m);
  v.Scaled("heading_spread_deg", c.heading_spread_rad, kRadToDeg);
  v.Number("dwell_s", c.dwell_s);
  v.Number("drive_speed_mps", c.drive_speed_mps);
  v.Number("lateral_spread_m", c.lateral_spread_m);
  v.Boolean("continuous", c.continuous);
  v.Number("weave_amplitude_m", c.weave_amplitude_m);
  v.Number("continuous_duration_s", c.continuous_duration_s);
  v.Number("gnss_rate_hz", c.gnss_rate_hz);
  v.Number("gnss_bias_sigma_m", c.gnss_bias_sigma_m);
  v.Number("gnss_bias_tau_s", c.gnss_bias_tau_s);
  v.Number("gnss_white_sigma_m", c.gnss_white_sigma_m);
  v.Number("float_fraction", c.float_fraction);
  v.Boolean("write_gst", c.write_gst);
  v.Number("heading_rate_hz", c.heading_rate_hz);
  v.Scaled("heading_white_sigma_deg", c.heading_white_sigma_rad, kRadToDeg);
  v.Scaled("heading_drift_deg_per_h", c.heading_drift_rad_per_s, kDegPerHourPerRadPerS);
  v.Scaled("heading_bias_deg", c.heading_bias_rad, kRadToDeg);
  v.Number("total_station_sigma_m", c.total_station_sigma_m);
  v.Number("control_sigma_m", c.control_sigma_m);
  v.Scaled("survey_rotation_deg", c.survey_rotation_rad, kRadToDeg);
  v.Number("survey_origin_x_m", c.survey_origin_x_m);
  v.Number("survey_origin_y_m", c.survey_origin_y_m);
  v.Number("lost_scan_fraction", c.lost_scan_fraction);
  v.Number("mixed_pixel_probability", c.mixed_pixel_probability);
  v.Number("start_time_s", c.start_time_s);
}

}  // namespace wallcal::io::fields
