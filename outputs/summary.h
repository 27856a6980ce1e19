// SPDX-License-Identifier: Apache-2.0
#pragma once
// The human summary calibrate prints: counts, the mount with its σ, the analysis, warnings.

#include <string>

#include "pipeline/calibration.h"

namespace wallcal::outputs {

std::string FormatSummary(const pipeline::CalibrationResult& result);

// "since FILE: x +1.2 mm, y -0.3 mm, yaw +0.012 deg (0.4, 0.1, 0.3 combined sigma)": the
// change line of the summary (one scanner, each of several, each relative transform); a
// relative transform compared with the previous file's inverse (Change::previous_inverted)
// adds "; the previous file holds it the other way round, inverted".
std::string ChangeText(const pipeline::Change& change);

}  // namespace wallcal::outputs
