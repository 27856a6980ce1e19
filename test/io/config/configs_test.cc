// SPDX-License-Identifier: Apache-2.0
// The files shipped in configs/ load, validate, and say what the code's defaults say.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "pipeline/calibrate_options.h"
#include "sim/simulation_config.h"
#include "io/config/session_reader.h"

namespace wallcal::io {
using pipeline::CalibrateOptions;
using pipeline::ReadCalibrateOptions;
using sim::ReadSimulationConfig;
using sim::SimulationConfig;
namespace {

namespace fs = std::filesystem;
const fs::path kConfigs = fs::path(WALLCAL_SOURCE_DIR) / "configs";

// configs/calibrate.yaml documents the defaults: it must not drift from io/options.h.
TEST(ShippedConfigTest, CalibrateYamlEqualsBuiltInDefaults) {
  const CalibrateOptions file = ReadCalibrateOptions((kConfigs / "calibrate.yaml").string());
  const CalibrateOptions d;
  const double tol = 1e-6;
  EXPECT_NEAR(file.detector.hough_rho_step_m, d.detector.hough_rho_step_m, tol);
  EXPECT_NEAR(file.detector.hough_theta_step_rad, d.detector.hough_theta_step_rad, tol);
  EXPECT_EQ(file.detector.min_inliers, d.detector.min_inliers);
  EXPECT_NEAR(file.detector.inlier_band_m, d.detector.inlier_band_m, tol);
  EXPECT_NEAR(file.detector.refine_sigma_factor, d.detector.refine_sigma_factor, tol);
  EXPECT_NEAR(file.detector.mixed_pixel_jump_m, d.detector.mixed_pixel_jump_m, tol);
  EXPECT_NEAR(file.detector.min_range_m, d.detector.min_range_m, tol);
  EXPECT_NEAR(file.detector.wide_angle_gate_rad, d.detector.wide_angle_gate_rad, tol);
  EXPECT_NEAR(file.detector.wide_offset_gate_m, d.detector.wide_offset_gate_m, tol);
  EXPECT_NEAR(file.detector.tight_angle_gate_rad, d.detector.tight_angle_gate_rad, tol);
  EXPECT_NEAR(file.detector.tight_offset_gate_m, d.detector.tight_offset_gate_m, tol);
  EXPECT_EQ(file.detector.tight_min_inliers, d.detector.tight_min_inliers);
  EXPECT_NEAR(file.detector.wall_extent_margin_m, d.detector.wall_extent_margin_m, tol);
  EXPECT_NEAR(file.alignment.max_gap_periods, d.alignment.max_gap_periods, tol);
  EXPECT_NEAR(file.alignment.stationary_speed_mps, d.alignment.stationary_speed_mps, tol);
  EXPECT_NEAR(file.alignment.stationary_yaw_rate_rps, d.alignment.stationary_yaw_rate_rps, tol);
  EXPECT_NEAR(file.alignment.stationary_window_s, d.alignment.stationary_window_s, tol);
  EXPECT_NEAR(file.alignment.min_dwell_s, d.alignment.min_dwell_s, tol);
  EXPECT_NEAR(file.alignment.dwell_guard_s, d.alignment.dwell_guard_s, tol);
  EXPECT_EQ(file.alignment.use_moving_scans, d.alignment.use_moving_scans);
  EXPECT_NEAR(file.alignment.segment_max_s, d.alignment.segment_max_s, tol);
  EXPECT_NEAR(file.solver.gnss_white_sigma_m, d.solver.gnss_white_sigma_m, tol);
  EXPECT_NEAR(file.solver.gnss_bias_sigma_m, d.solver.gnss_bias_sigma_m, tol);
  EXPECT_EQ(file.solver.use_gst_sigma, d.solver.use_gst_sigma);
  EXPECT_NEAR(file.solver.heading_sigma_rad, d.solver.heading_sigma_rad, tol);
  EXPECT_NEAR(file.solver.heading_drift_sigma_rad_per_s, d.solver.heading_drift_sigma_rad_per_s,
              1e-12);
  EXPECT_NEAR(file.solver.control_sigma_m, d.solver.control_sigma_m, tol);
  EXPECT_NEAR(file.solver.total_station_sigma_m, d.solver.total_station_sigma_m, tol);
  EXPECT_NEAR(file.solver.rotation_sigma_rad, d.solver.rotation_sigma_rad, tol);
  EXPECT_NEAR(file.solver.huber_scale, d.solver.huber_scale, tol);
  EXPECT_EQ(file.solver.max_iterations, d.solver.max_iterations);
  EXPECT_NEAR(file.solver.min_heading_spread_rad, d.solver.min_heading_spread_rad, tol);
  EXPECT_EQ(file.solver.min_observations, d.solver.min_observations);
  EXPECT_EQ(file.solver.min_stations, d.solver.min_stations);
  EXPECT_NEAR(file.solver.gnss_bias_tau_s, d.solver.gnss_bias_tau_s, tol);
  EXPECT_NEAR(file.solver.time_offset_sigma_s, d.solver.time_offset_sigma_s, tol);
  EXPECT_NEAR(file.solver.max_sigma_xy_m, d.solver.max_sigma_xy_m, tol);
  EXPECT_NEAR(file.solver.max_sigma_yaw_rad, d.solver.max_sigma_yaw_rad, tol);
  EXPECT_EQ(file.solver.bootstrap_samples, d.solver.bootstrap_samples);
  EXPECT_NEAR(file.acceptance.max_sigma_xy_m, d.acceptance.max_sigma_xy_m, tol);
  EXPECT_NEAR(file.acceptance.max_sigma_yaw_rad, d.acceptance.max_sigma_yaw_rad, tol);
  EXPECT_NEAR(file.acceptance.max_change_xy_m, d.acceptance.max_change_xy_m, tol);
  EXPECT_NEAR(file.acceptance.max_change_yaw_rad, d.acceptance.max_change_yaw_rad, tol);
  EXPECT_NEAR(file.acceptance.max_change_sigmas, d.acceptance.max_change_sigmas, tol);
  EXPECT_EQ(file.alignment.moving_scans_if_few_stations, d.alignment.moving_scans_if_few_stations);
  EXPECT_EQ(file.first_pass_max_scans, d.first_pass_max_scans);
}

TEST(ShippedConfigTest, EverySimulationScenarioLoadsAndNamesAPreset) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kConfigs / "simulate")) {
    if (entry.path().extension() != ".yaml") continue;
    const SimulationConfig config = ReadSimulationConfig(entry.path().string());
    EXPECT_NO_THROW(LoadScannerPreset(config.scanner_model, {(kConfigs / "scanners").string()}))
        << entry.path();
    ++count;
  }
  EXPECT_GE(count, 4);
}

}  // namespace
}  // namespace wallcal::io
