// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's test fixtures: the shipped presets, cheap and perfect variants of them, the
// default and noise-free configs, and a run collected in memory. Shared by the simulator's tests.

#include <cstdint>
#include <string>
#include <vector>

#include "common/angles.h"
#include "sim/simulator.h"
#include "test/support/shipped_presets.h"

namespace wallcal::sim::testing_fixtures {

// The shipped presets (configs/scanners/*.yaml).
inline io::ScannerPreset SickLms291() { return testing_support::ShippedPreset("sick_lms291"); }
inline io::ScannerPreset SickLms200() { return testing_support::ShippedPreset("sick_lms200"); }
inline io::ScannerPreset HokuyoUrg04lx() {
  return testing_support::ShippedPreset("hokuyo_urg04lx");
}

// A few beams at 1 Hz: for long runs where only GNSS, heading or scan counts matter.
inline io::ScannerPreset CheapPreset(double rate_hz = 1.0) {
  io::ScannerPreset p = SickLms291();
  p.name = "cheap";
  p.num_beams = 3;
  p.start_angle_rad = -10.0 * kDegToRad;
  p.angular_step_rad = 10.0 * kDegToRad;
  p.rate_hz = rate_hz;
  return p;
}

// SICK LMS 291 geometry with a perfect range: z = y exactly (up to float storage).
inline io::ScannerPreset PerfectPreset() {
  io::ScannerPreset p = SickLms291();
  p.range_sigma_m = 0.0;
  p.sim_scale_n = 1.0;
  p.sim_offset_c_m = 0.0;
  p.range_resolution_m = 1e-12;
  return p;
}

// An upright wall from (x0, y0) to (x1, y1), surveyed at the default heights.
inline sim::SimWall Wall(const std::string& id, const std::string& code, double x0_m,
                         double y0_m, double x1_m, double y1_m, double height_m = 3.0) {
  sim::SimWall wall;
  wall.id = id;
  wall.code = code;
  wall.x0_m = x0_m;
  wall.y0_m = y0_m;
  wall.x1_m = x1_m;
  wall.y1_m = y1_m;
  wall.height_m = height_m;
  return wall;
}

// The vehicle's pose at start_time_s: its antenna at antenna_enu_m heading yaw_enu_rad, level.
inline SimTruthPose PoseAt(const sim::SimulationConfig& config,
                           const Eigen::Vector2d& antenna_enu_m, double yaw_enu_rad) {
  SimTruthPose pose;
  pose.stamp_s = config.start_time_s;
  pose.antenna_enu_m = antenna_enu_m;
  pose.yaw_enu_rad = yaw_enu_rad;
  pose.stationary = false;
  return pose;
}

inline sim::SimulationConfig DefaultConfig() { return WithDefaultWalls(sim::SimulationConfig{}); }

inline sim::SimulationConfig NoiseFreeConfig() {
  sim::SimulationConfig c = DefaultConfig();
  c.gnss_bias_sigma_m = 0.0;
  c.gnss_white_sigma_m = 0.0;
  c.heading_white_sigma_rad = 0.0;
  c.heading_drift_rad_per_s = 0.0;
  c.heading_bias_rad = 0.0;
  c.total_station_sigma_m = 0.0;
  c.control_sigma_m = 0.0;
  c.lost_scan_fraction = 0.0;
  c.mixed_pixel_probability = 0.0;
  return c;
}

struct Collected {
  SimulatedSession session;
  std::vector<io::ScanRecord> scans;
};

inline Collected RunSim(const sim::SimulationConfig& config, const io::ScannerPreset& preset,
                        uint64_t seed) {
  Collected out;
  out.session =
      Simulate(config, preset, seed, [&out](const io::ScanRecord& s) { out.scans.push_back(s); });
  return out;
}

}  // namespace wallcal::sim::testing_fixtures
