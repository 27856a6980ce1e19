// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's test fixtures: the shipped presets, cheap and perfect variants of them, the
// default and noise-free configs, and a run collected in memory. Shared by the simulator's tests.

#include <cstdint>
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
