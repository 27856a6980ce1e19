// SPDX-License-Identifier: Apache-2.0
#pragma once
// simulate's output: a whole session folder written from a simulation.

#include <cstdint>
#include <string>

#include "sim/simulation_config.h"

namespace wallcal::sim {

// Writes a session folder (session.yaml, scans.clf, gnss.nmea, heading.nmea, survey.csv) and
// truth.yaml into `dir` (created if missing). Every file is written to a temporary name and
// renamed, so an interrupted run leaves no half-written file behind; session.yaml comes last.
struct SimulateSummary {
  int64_t scans_written = 0, scans_lost = 0, fixes = 0, headings = 0, survey_points = 0;
  int64_t ground_returns = 0;  // beams that returned from the ground (a 3-D site), all scanners
  double duration_s = 0.0;
};
SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir);

}  // namespace wallcal::sim
