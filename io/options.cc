#include "io/options.h"

#include <cmath>
#include <sstream>
#include <tuple>
#include "common/angles.h"

namespace wallcal::io {
namespace {
// Messages name the YAML key (angles in degrees there), so the user can find what to change.
std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

[[noreturn]] void Fail(const std::string& key, const std::string& requirement,
                       const std::string& got) {
  throw OptionError(key, key + " must be " + requirement + ", got " + got);
}

// Cells of the accumulator DetectWall allocates for a gate (calib/wall_detector.cc: the gate's
// width in steps plus margins, in both directions).
double HoughCells(double angle_gate_rad, double offset_gate_m, double theta_step_rad,
                  double rho_step_m) {
  return (2.0 * angle_gate_rad / theta_step_rad + 3.0) * (2.0 * offset_gate_m / rho_step_m + 3.0);
}

void CheckFinite(const std::string& key, double value) {
  if (!std::isfinite(value)) Fail(key, "a finite number", Number(value));
}
void CheckPositive(const std::string& key, double value) {
  if (!(std::isfinite(value) && value > 0.0)) Fail(key, "> 0", Number(value));
}
void CheckNonNegative(const std::string& key, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) Fail(key, ">= 0", Number(value));
}
void CheckRange(const std::string& key, double value, double lo, double hi) {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    Fail(key, "in [" + Number(lo) + ", " + Number(hi) + "]", Number(value));
  }
}
void CheckAtLeast(const std::string& key, int value, int lo) {
  if (value < lo) Fail(key, ">= " + std::to_string(lo), std::to_string(value));
}
// Angles are checked in the unit the user wrote them in.
void CheckAnglePositive(const std::string& key_deg, double rad, double max_deg) {
  const double deg = rad * kRadToDeg;
  if (!(std::isfinite(deg) && deg > 0.0 && deg <= max_deg)) {
    Fail(key_deg, "in (0, " + Number(max_deg) + "]", Number(deg));
  }
}

}  // namespace

void DetectorOptions::Validate() const {
  CheckPositive("detector.hough_rho_step_m", hough_rho_step_m);
  CheckRange("detector.hough_theta_step_deg", hough_theta_step_rad * kRadToDeg, 0.001, 10.0);
  CheckAtLeast("detector.min_inliers", min_inliers, 3);
  CheckAtLeast("detector.tight_min_inliers", tight_min_inliers, 3);
  CheckPositive("detector.inlier_band_m", inlier_band_m);
  CheckPositive("detector.refine_sigma_factor", refine_sigma_factor);
  CheckPositive("detector.mixed_pixel_jump_m", mixed_pixel_jump_m);
  CheckNonNegative("detector.min_range_m", min_range_m);
  CheckAnglePositive("detector.wide_angle_gate_deg", wide_angle_gate_rad, 90.0);
  CheckPositive("detector.wide_offset_gate_m", wide_offset_gate_m);
  CheckAnglePositive("detector.tight_angle_gate_deg", tight_angle_gate_rad, 90.0);
  CheckPositive("detector.tight_offset_gate_m", tight_offset_gate_m);
  CheckNonNegative("detector.wall_extent_margin_m", wall_extent_margin_m);
  CheckRange("detector.hough_rho_step_m", hough_rho_step_m, 1e-4, 1.0);
  // Tiny steps make an accumulator no memory holds (an OpenCV assertion, once): bounded here.
  for (const auto& [angle_rad, offset_m, name] :
       {std::tuple{wide_angle_gate_rad, wide_offset_gate_m, "wide"},
        std::tuple{tight_angle_gate_rad, tight_offset_gate_m, "tight"}}) {
    const double cells = HoughCells(angle_rad, offset_m, hough_theta_step_rad, hough_rho_step_m);
    if (!(cells <= kMaxHoughCells)) {
      Fail("detector.hough_rho_step_m",
           "large enough that the " + std::string(name) +
               " gate's Hough accumulator has at most " + Number(kMaxHoughCells) +
               " cells (with detector.hough_theta_step_deg " +
               Number(hough_theta_step_rad * kRadToDeg) + ")",
           Number(hough_rho_step_m) + " (" + Number(cells) + " cells)");
    }
  }
}

void AlignmentOptions::Validate() const {
  CheckPositive("alignment.max_gap_periods", max_gap_periods);
  CheckPositive("alignment.stationary_speed_mps", stationary_speed_mps);
  if (!(std::isfinite(stationary_yaw_rate_rps) && stationary_yaw_rate_rps > 0.0)) {
    Fail("alignment.stationary_yaw_rate_deg_per_s", "> 0",
         Number(stationary_yaw_rate_rps * kRadToDeg));
  }
  CheckPositive("alignment.stationary_window_s", stationary_window_s);
  CheckNonNegative("alignment.min_dwell_s", min_dwell_s);
  CheckNonNegative("alignment.dwell_guard_s", dwell_guard_s);
  CheckPositive("alignment.segment_max_s", segment_max_s);
  CheckNonNegative("alignment.moving_max_time_offset_sigma_s", moving_max_time_offset_sigma_s);
}

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

void AcceptanceOptions::Validate() const {
  CheckPositive("acceptance.max_sigma_xy_m", max_sigma_xy_m);
  CheckAnglePositive("acceptance.max_sigma_yaw_deg", max_sigma_yaw_rad, 180.0);
  CheckPositive("acceptance.max_change_xy_m", max_change_xy_m);
  CheckAnglePositive("acceptance.max_change_yaw_deg", max_change_yaw_rad, 180.0);
  CheckPositive("acceptance.max_change_sigmas", max_change_sigmas);
}

void CalibrateOptions::Validate() const {
  detector.Validate();
  alignment.Validate();
  solver.Validate();
  acceptance.Validate();
  CheckAtLeast("first_pass_max_scans", first_pass_max_scans, 1);
}

void SimulationConfig::Validate() const {
  const std::string s = "simulation.";
  CheckRange(s + "site_lat_deg", site_lat_deg, -80.0, 84.0);  // UTM's latitude band
  CheckRange(s + "site_lon_deg", site_lon_deg, -180.0, 180.0);
  CheckFinite(s + "site_height_m", site_height_m);
  if (name.empty()) Fail(s + "name", "non-empty", "\"\"");
  if (scanner_model.empty()) Fail(s + "scanner_model", "non-empty", "\"\"");
  if (!(std::isfinite(log_every_n) && log_every_n >= 1.0)) {
    Fail(s + "log_every_n", ">= 1", Number(log_every_n));
  }
  CheckFinite(s + "scanner_time_offset_s", scanner_time_offset_s);
  CheckFinite(s + "mount_x_m", mount_x_m);
  CheckFinite(s + "mount_y_m", mount_y_m);
  CheckRange(s + "mount_yaw_deg", mount_yaw_rad * kRadToDeg, -180.0, 180.0);
  for (size_t i = 0; i < walls.size(); ++i) {
    const SimWall& wall = walls[i];
    const std::string w = s + "walls[" + std::to_string(i) + "].";
    if (wall.id.empty()) Fail(w + "id", "non-empty", "\"\"");
    CheckFinite(w + "x0_m", wall.x0_m);
    CheckFinite(w + "y0_m", wall.y0_m);
    CheckFinite(w + "x1_m", wall.x1_m);
    CheckFinite(w + "y1_m", wall.y1_m);
    const double length_m = std::hypot(wall.x1_m - wall.x0_m, wall.y1_m - wall.y0_m);
    if (!(length_m > 0.0)) Fail(w + "x1_m/y1_m", "a different point from x0_m/y0_m", "the same");
    CheckPositive(w + "height_m", wall.height_m);
    CheckPositive(w + "survey_spacing_m", wall.survey_spacing_m);
  }
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const std::string o = s + "obstacles[" + std::to_string(i) + "].";
    CheckFinite(o + "x_m", obstacles[i].x_m);
    CheckFinite(o + "y_m", obstacles[i].y_m);
    CheckPositive(o + "radius_m", obstacles[i].radius_m);
  }
  CheckAtLeast(s + "num_stations", num_stations, 1);
  CheckPositive(s + "station_distance_m", station_distance_m);
  CheckRange(s + "heading_spread_deg", heading_spread_rad * kRadToDeg, 0.0, 360.0);
  CheckNonNegative(s + "dwell_s", dwell_s);
  CheckPositive(s + "drive_speed_mps", drive_speed_mps);
  CheckNonNegative(s + "lateral_spread_m", lateral_spread_m);
  CheckPositive(s + "gnss_rate_hz", gnss_rate_hz);
  CheckNonNegative(s + "gnss_bias_sigma_m", gnss_bias_sigma_m);
  CheckPositive(s + "gnss_bias_tau_s", gnss_bias_tau_s);
  CheckNonNegative(s + "gnss_white_sigma_m", gnss_white_sigma_m);
  CheckRange(s + "float_fraction", float_fraction, 0.0, 1.0);
  CheckPositive(s + "heading_rate_hz", heading_rate_hz);
  CheckNonNegative(s + "heading_white_sigma_deg", heading_white_sigma_rad * kRadToDeg);
  CheckFinite(s + "heading_drift_deg_per_h", heading_drift_rad_per_s * kRadToDeg * 3600.0);
  CheckFinite(s + "heading_bias_deg", heading_bias_rad * kRadToDeg);
  CheckNonNegative(s + "total_station_sigma_m", total_station_sigma_m);
  CheckNonNegative(s + "control_sigma_m", control_sigma_m);
  CheckFinite(s + "survey_rotation_deg", survey_rotation_rad * kRadToDeg);
  CheckFinite(s + "survey_origin_x_m", survey_origin_x_m);
  CheckFinite(s + "survey_origin_y_m", survey_origin_y_m);
  if (!(lost_scan_fraction >= 0.0 && lost_scan_fraction < 1.0)) {
    Fail(s + "lost_scan_fraction", "in [0, 1)", Number(lost_scan_fraction));
  }
  CheckRange(s + "mixed_pixel_probability", mixed_pixel_probability, 0.0, 1.0);
  CheckNonNegative(s + "start_time_s", start_time_s);
  CheckRange(s + "gnss_latency_s", gnss_latency_s, 0.0, 10.0);
  CheckRange(s + "gnss_jitter_s", gnss_jitter_s, 0.0, 1.0);
  CheckRange(s + "heading_latency_s", heading_latency_s, 0.0, 10.0);
  CheckRange(s + "scanner_latency_s", scanner_latency_s, 0.0, 10.0);
  const std::string t = s + "scanner_truth.";
  if (!std::isnan(truth_scale_n)) CheckRange(t + "n", truth_scale_n, 0.5, 1.5);
  if (!std::isnan(truth_offset_c_m)) CheckRange(t + "c_m", truth_offset_c_m, -1.0, 1.0);
  if (!std::isnan(truth_sigma_m)) CheckRange(t + "sigma_m", truth_sigma_m, 0.0, 1.0);
  if (!std::isnan(truth_resolution_m)) CheckRange(t + "resolution_m", truth_resolution_m, 1e-6, 1.0);
  if (!std::isnan(truth_max_incidence_rad)) {
    CheckRange(t + "max_incidence_deg", truth_max_incidence_rad * kRadToDeg, 1.0, 90.0);
  }
  CheckRange(t + "drift.amplitude_m", truth_drift_amplitude_m, -1.0, 1.0);
  CheckNonNegative(t + "drift.time_constant_s", truth_drift_time_constant_s);
  CheckNonNegative(s + "station_distance_far_m", station_distance_far_m);
  CheckRange(s + "drive_reverse_m", drive_reverse_m, 0.0, 100.0);
  CheckRange(s + "weave_turn_deg", weave_turn_rad * kRadToDeg, 0.0, 90.0);
}

}  // namespace wallcal::io
