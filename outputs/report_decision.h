// SPDX-License-Identifier: Apache-2.0
#pragma once
// The top of the report: the decision section (verdict with its reasons, the error budget, the
// change since the previous calibration, the error against truth.yaml when known). Internal to
// outputs/report.cc; renders the result only.

#include <string>

#include "pipeline/calibration.h"

namespace wallcal::outputs {

// <section id="decision">...</section>
std::string DecisionSectionHtml(const pipeline::CalibrationResult& result);

}  // namespace wallcal::outputs
