// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's report as text for people and as one JSON object.

#include <string>

#include "guide/guide.h"

namespace wallcal::guide {

// The stations, the predicted σ against the tolerances, enough yes/no and the next stops.
std::string GuideText(const GuideReport& report);

// One object: {"stations": N, "predicted_sigma": {"x_m": …, "y_m": …, "yaw_deg": …},
// "enough": true|false, "next": [{"vehicle_to_wall_deg": …, "distance_m": …, "dwell_s": …,
// "wait_s": …}, …]}; a σ not known yet is null. For --plan, "next" lists the plan's stops.
std::string GuideJson(const GuideReport& report);

}  // namespace wallcal::guide
