// SPDX-License-Identifier: Apache-2.0
#pragma once
// The human summary calibrate prints: counts, the mount with its σ, the analysis, warnings.

#include <string>

#include "pipeline/calibration.h"

namespace wallcal::outputs {

std::string FormatSummary(const pipeline::CalibrationResult& result);

}  // namespace wallcal::outputs
