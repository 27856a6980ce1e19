// SPDX-License-Identifier: Apache-2.0
#pragma once
// simulate's output: a whole session folder written from a simulation.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/types.h"
#include "sim/simulation_config.h"

namespace wallcal::sim {

struct SimulatedSession;

// Writes a session folder (session.yaml, scans.clf, gnss.nmea, heading.nmea, survey.csv) and
// truth.yaml into `dir` (created if missing). Every file is written to a temporary name and
// renamed, so an interrupted run leaves no half-written file behind; session.yaml comes last.
// A simulated attitude stream (SimulatedSession::attitudes, when not empty) is written as
// $PASHR lines (config.attitude_sentence "avr": $PTNL,AVR) in heading.nmea, in time order with
// the HDT lines, or with config.attitude_own_log in attitude.nmea; session.yaml then names it
// under `attitude:`. truth.yaml records each scanner unit's range errors as applied (given or
// drawn, UnitRangeErrors): simulation.range_scale_error and range_offset_error_m for one
// scanner, the same keys on each entry of simulation.scanners for several; none when none.
struct SimulateSummary {
  int64_t scans_written = 0, scans_lost = 0, fixes = 0, headings = 0, survey_points = 0;
  int64_t ground_returns = 0;  // beams that returned from the ground (a 3-D site), all scanners
  int64_t attitudes = 0;
  double duration_s = 0.0;
};
SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir);

// As above, with `edit` applied to the simulated session (the first scanner's run) before its
// GNSS, heading, attitude and survey files are written; its scans are written already. For
// tests: a stream the simulator does not make, or a hostile one.
using SimulatedSessionEdit = std::function<void(SimulatedSession&)>;
SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir, const SimulatedSessionEdit& edit);

// The heading (clockwise from north, rad, [0, 2π)) that `headings` (in time order) give at
// stamp_s: interpolated along the shorter arc between the samples around it, the first or the
// last one outside them; NaN without samples. The attitude sentences' heading and yaw, and the
// yaw of a simulated recording's Imu orientation.
double HeadingAt(const std::vector<io::HeadingSample>& headings, double stamp_s);

}  // namespace wallcal::sim
