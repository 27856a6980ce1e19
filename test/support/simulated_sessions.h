// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whole simulated sessions for the tests that calibrate them: the shipped scenarios
// (configs/simulate/), the two-wall benchmark with only the line fits' errors left, and a
// session written into this test program's scratch folder.

#include <cstdint>
#include <filesystem>
#include <string>

#include "common/angles.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"
#include "sim/simulator.h"
#include "test/support/scratch_files.h"
#include "test/support/shipped_presets.h"

namespace wallcal::testing_support {

// configs/simulate/<name>.yaml, with the default walls when it names none.
inline sim::SimulationConfig ShippedScenario(const std::string& name) {
  return sim::WithDefaultWalls(sim::ReadSimulationConfig(ShippedScenarioPath(name)));
}

// The two-wall benchmark (bench_lms291_two_walls) with the GNSS, heading and survey noise off:
// the only errors left are the line fits'.
inline sim::SimulationConfig TwoWallsWithOnlyLineFitErrors() {
  sim::SimulationConfig config =
      sim::ReadSimulationConfig(ShippedScenarioPath("bench_lms291_two_walls"));
  config.gnss_bias_sigma_m = config.gnss_white_sigma_m = 0.0;
  config.heading_white_sigma_rad = config.heading_drift_rad_per_s = 0.0;
  config.total_station_sigma_m = config.control_sigma_m = 0.0;
  return config;
}

// `config` simulated with `seed` and written as a session into the empty scratch folder `name`.
inline std::filesystem::path SimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                              const std::string& name) {
  const std::filesystem::path dir = FreshScratchDir(name);
  sim::WriteSimulatedSession(config, seed, dir.string());
  return dir;
}

// The sample's scenario (lms291_sapporo) with 8 stations whose headings spread over only 4°,
// seed 21, written into the empty scratch folder `name`: too narrow to determine the mount.
inline std::filesystem::path NarrowHeadingsSession(const std::string& name) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(ShippedScenarioPath("lms291_sapporo"));
  config.heading_spread_rad = 4.0 * kDegToRad;
  config.num_stations = 8;
  return SimulatedSession(config, 21, name);
}

}  // namespace wallcal::testing_support
